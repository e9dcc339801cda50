// gpu::Scan against std::exclusive_scan, on block-size edges and multi-level sizes.
#include <gtest/gtest.h>

#include <numeric>
#include <random>
#include <vector>

#include "gpu/dispatcher.h"
#include "gpu/scan.h"
#include "support/gpu.h"
#include "vk/buffer.h"

namespace wetdem::test {

class Scan : public GpuTest {
 protected:
  // Scans `in` on the GPU (total written just after the data); returns (scanned, total).
  std::pair<std::vector<uint32_t>, uint32_t> run(const std::vector<uint32_t>& in) {
    const uint32_t n = uint32_t(in.size());
    vk::Buffer data(gpu(), uint64_t(n) * 4), total(gpu(), 4);
    data.upload(in);
    total.upload(std::vector<uint32_t>{0xdeadbeefu});  // must be overwritten, also for n = 0
    gpu::Scan scan(gpu(), n);
    gpu::DirectDispatcher disp;
    gpu().submit_now([&](VkCommandBuffer cb) { scan.record(cb, disp, data.address(), n, total.address()); });
    return {data.download_as<uint32_t>(n), total.download_as<uint32_t>(1)[0]};
  }
  void check(const std::vector<uint32_t>& in) {
    std::vector<uint32_t> want(in.size());
    std::exclusive_scan(in.begin(), in.end(), want.begin(), 0u);
    const uint32_t want_total = std::accumulate(in.begin(), in.end(), 0u);
    auto [got, total] = run(in);
    ASSERT_EQ(got.size(), want.size());
    for (size_t i = 0; i < want.size(); ++i) ASSERT_EQ(got[i], want[i]) << "n=" << in.size() << " i=" << i;
    EXPECT_EQ(total, want_total) << "n=" << in.size();
  }
  static std::vector<uint32_t> random(size_t n, uint32_t max, uint32_t seed) {
    std::mt19937 rng(seed);
    std::vector<uint32_t> v(n);
    for (auto& x : v) x = max == 0xffffffffu ? uint32_t(rng()) : uint32_t(rng() % (max + 1));
    return v;
  }
};

TEST_F(Scan, EmptyWritesZeroTotal) {
  check({});
}

TEST_F(Scan, SizesAroundOneBlock) {
  for (size_t n : {1, 2, 255, 256, 257, 2047, 2048, 2049}) check(random(n, 1000, uint32_t(n)));
}

TEST_F(Scan, TwoLevels) {
  check(random(65537, 1000, 7));
  check(std::vector<uint32_t>(2048 * 2048, 1));  // exactly two full levels
}

TEST_F(Scan, ThreeLevels) {
  check(random(3000000, 1000, 11));
}

TEST_F(Scan, WrapsLikeUint32) {
  check(random(5000, 0xffffffffu, 3));
}

TEST_F(Scan, TotalMayBeOmittedAndSubrangeScanned) {
  // total_addr = 0 writes no total; the scan only touches [0, n).
  std::vector<uint32_t> in = random(10000, 50, 5);
  vk::Buffer data(gpu(), in.size() * 4);
  data.upload(in);
  gpu::Scan scan(gpu(), 20000);
  gpu::DirectDispatcher disp;
  gpu().submit_now([&](VkCommandBuffer cb) { scan.record(cb, disp, data.address(), 6000, 0); });
  auto got = data.download_as<uint32_t>(in.size());
  std::vector<uint32_t> want = in;
  std::exclusive_scan(in.begin(), in.begin() + 6000, want.begin(), 0u);
  EXPECT_EQ(got, want);
}

TEST_F(Scan, RejectsMoreThanMaxN) {
  gpu::Scan scan(gpu(), 100);
  gpu::DirectDispatcher disp;
  EXPECT_THROW(scan.record(VK_NULL_HANDLE, disp, 0, 101, 0), std::invalid_argument);
}

}  // namespace wetdem::test
