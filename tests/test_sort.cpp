// gpu::RadixSort against std::stable_sort by the low key_bits bits: equality of the (key, value) sequences
// checks sortedness, the unchanged multiset of pairs and stability at once.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "gpu/dispatcher.h"
#include "gpu/radix_sort.h"
#include "support/gpu.h"
#include "vk/buffer.h"

namespace wetdem::test {

namespace {
using Pairs = std::pair<std::vector<uint32_t>, std::vector<uint32_t>>;

uint32_t low_mask(uint32_t bits) {
  return bits >= 32 ? 0xffffffffu : (1u << bits) - 1u;
}

Pairs reference_sort(const std::vector<uint32_t>& keys, const std::vector<uint32_t>& vals,
                     uint32_t key_bits) {
  std::vector<size_t> idx(keys.size());
  for (size_t i = 0; i < idx.size(); ++i) idx[i] = i;
  const uint32_t m = low_mask(key_bits);
  std::stable_sort(idx.begin(), idx.end(), [&](size_t a, size_t b) { return (keys[a] & m) < (keys[b] & m); });
  Pairs out;
  for (size_t i : idx) {
    out.first.push_back(keys[i]);
    out.second.push_back(vals[i]);
  }
  return out;
}

std::vector<uint32_t> iota(size_t n) {
  std::vector<uint32_t> v(n);
  for (size_t i = 0; i < n; ++i) v[i] = uint32_t(i);
  return v;
}

std::vector<uint32_t> random_keys(size_t n, uint32_t mask, uint32_t seed) {
  std::mt19937 rng(seed);
  std::vector<uint32_t> v(n);
  for (auto& x : v) x = rng() & mask;
  return v;
}

// Forwards to a DirectDispatcher and logs (kernel, groups) of every dispatch.
class LoggingDispatcher final : public gpu::Dispatcher {
 public:
  void dispatch(VkCommandBuffer cb, const vk::Kernel& k, uint32_t groups, const void* push,
                uint32_t push_bytes) override {
    log.emplace_back(k.name(), groups);
    direct_.dispatch(cb, k, groups, push, push_bytes);
  }
  std::vector<std::pair<std::string, uint32_t>> log;

 private:
  gpu::DirectDispatcher direct_;
};
}  // namespace

class Sort : public GpuTest {
 protected:
  // Sorts on the GPU with a sorter of capacity max(n, capacity) (a larger one exercises n < max_n).
  Pairs run(const std::vector<uint32_t>& keys, const std::vector<uint32_t>& vals, uint32_t key_bits,
            uint32_t capacity = 0, bool one_tile = true) {
    const uint32_t n = uint32_t(keys.size());
    vk::Buffer k(gpu(), uint64_t(n) * 4), v(gpu(), uint64_t(n) * 4);
    k.upload(keys);
    v.upload(vals);
    gpu::RadixSort sort(gpu(), std::max(n, capacity));
    sort.set_one_tile(one_tile);
    gpu::DirectDispatcher disp;
    gpu().submit_now(
        [&](VkCommandBuffer cb) { sort.record(cb, disp, k.address(), v.address(), n, key_bits); });
    return {k.download_as<uint32_t>(n), v.download_as<uint32_t>(n)};
  }
  void check(const std::vector<uint32_t>& keys, uint32_t key_bits, const std::string& what) {
    check(keys, iota(keys.size()), key_bits, what);
  }
  void check(const std::vector<uint32_t>& keys, const std::vector<uint32_t>& vals, uint32_t key_bits,
             const std::string& what) {
    Pairs want = reference_sort(keys, vals, key_bits);
    Pairs got = run(keys, vals, key_bits);
    const uint32_t m = low_mask(key_bits);
    for (size_t i = 1; i < got.first.size(); ++i)
      ASSERT_LE(got.first[i - 1] & m, got.first[i] & m) << what << ": not sorted at " << i;
    for (size_t i = 0; i < want.first.size(); ++i) {
      ASSERT_EQ(got.first[i], want.first[i]) << what << ": key at " << i;
      ASSERT_EQ(got.second[i], want.second[i]) << what << ": value at " << i << " (stability)";
    }
  }
};

TEST_F(Sort, TinySizes) {
  for (size_t n : {0, 1, 2, 255, 256, 257, 2047, 2048, 2049, 4097})
    check(random_keys(n, 0xffffffffu, uint32_t(n)), 32, "n=" + std::to_string(n));
}

TEST_F(Sort, UniformRandomForSeveralKeyBits) {
  for (uint32_t bits : {1u, 5u, 17u, 32u})
    check(random_keys(50000, low_mask(bits), bits), bits, "key_bits=" + std::to_string(bits));
}

TEST_F(Sort, BitsAboveKeyBitsAreIgnored) {
  // Full 32-bit keys sorted by their low 5 (or 17) bits: the high bits ride along in input order.
  check(random_keys(30000, 0xffffffffu, 1), 5, "key_bits=5");
  check(random_keys(30000, 0xffffffffu, 2), 17, "key_bits=17");
}

TEST_F(Sort, ClusteredKeysAreStable) {
  // Many equal keys, few distinct (all in one digit bucket for most passes): stability is what is tested.
  std::mt19937 rng(3);
  std::vector<uint32_t> keys(100000);
  const uint32_t distinct[] = {7u, 0x12345u, 0x12346u, 0xfffffu};
  for (auto& x : keys) x = distinct[rng() % 4];
  check(keys, 20, "4 distinct keys");
  check(std::vector<uint32_t>(20000, 42u), 32, "all equal");
}

TEST_F(Sort, SortedAndReverseInputs) {
  std::vector<uint32_t> up(40000), down(40000);
  for (size_t i = 0; i < up.size(); ++i) {
    up[i] = uint32_t(i * 3);
    down[i] = uint32_t((up.size() - i) * 3);
  }
  check(up, 17, "sorted");
  check(down, 17, "reverse");
}

TEST_F(Sort, ValuesTravelWithKeys) {
  // Arbitrary values (not indices), duplicates among them.
  check(random_keys(20000, 0xff, 8), random_keys(20000, 0xfff, 9), 8, "random values");
}

TEST_F(Sort, OddAndEvenPassCountsAndNoPass) {
  // 1 pass (odd: copy back), 2 passes (even), 0 key bits (nothing moves).
  for (uint32_t bits : {4u, 8u, 12u, 0u})
    check(random_keys(10000, 0xffff, bits + 20), bits, "b=" + std::to_string(bits));
}

TEST_F(Sort, SmallerThanCapacity) {
  auto keys = random_keys(3000, 0xffffffffu, 4);
  Pairs want = reference_sort(keys, iota(keys.size()), 32);
  EXPECT_EQ(run(keys, iota(keys.size()), 32, 100000), want);
}

TEST_F(Sort, LargeMillion) {
  check(random_keys(1 << 20, 0xffffffffu, 5), 32, "n=2^20");
}

TEST_F(Sort, DeterministicAcrossRuns) {
  std::mt19937 rng(6);
  std::vector<uint32_t> keys(300000);
  for (auto& x : keys) x = rng() % 97;  // many ties
  auto vals = random_keys(keys.size(), 0xffffffffu, 7);
  Pairs a = run(keys, vals, 7), b = run(keys, vals, 7);
  EXPECT_TRUE(a == b) << "two runs differ";
}

TEST_F(Sort, DispatchSizesDependOnlyOnN) {
  // What the gated rebuild relies on: the same n records the same dispatches, whatever the data.
  const uint32_t n = 5000;
  vk::Buffer k1(gpu(), n * 4), v1(gpu(), n * 4), k2(gpu(), n * 4), v2(gpu(), n * 4);
  k1.upload(random_keys(n, 0xffffffffu, 1));
  k2.upload(std::vector<uint32_t>(n, 3u));
  gpu::RadixSort sort(gpu(), 10000);
  LoggingDispatcher d1, d2;
  gpu().submit_now([&](VkCommandBuffer cb) {
    sort.record(cb, d1, k1.address(), v1.address(), n, 17);
    sort.record(cb, d2, k2.address(), v2.address(), n, 17);
  });
  EXPECT_EQ(d1.log, d2.log);
  // Per pass: count, scan of 3 tiles x 16 digits (one block: 1 dispatch), scatter; 5 passes (odd): copy.
  EXPECT_EQ(d1.log.size(), 5u * (1 + 1 + 1) + 1);
}

// Up to one tile (2,048 pairs) the whole sort is one dispatch (radix_sort_tile.comp): the same pairs in the
// same order as the multi-pass sort and std::stable_sort, at every pass count and with many ties.
TEST_F(Sort, OneTileSortIsTheMultiPassSort) {
  for (size_t n : {1, 2, 7, 255, 410, 1000, 2047, 2048})
    for (uint32_t bits : {0u, 1u, 4u, 5u, 12u, 17u, 32u}) {
      const std::string what = "n=" + std::to_string(n) + " key_bits=" + std::to_string(bits);
      const auto keys = random_keys(n, bits == 1 ? 0xffffffffu : 0x3f3u, uint32_t(n + bits));
      const auto vals = random_keys(n, 0xffffffffu, uint32_t(7 * n + bits));
      const Pairs want = reference_sort(keys, vals, bits);
      EXPECT_EQ(run(keys, vals, bits, 0, true), want) << what << ", one tile";
      EXPECT_EQ(run(keys, vals, bits, 0, false), want) << what << ", multi-pass";
    }
  // One dispatch up to a tile, the passes beyond (and with the one-tile sort off).
  vk::Buffer k(gpu(), 4096 * 4), v(gpu(), 4096 * 4);
  gpu::RadixSort sort(gpu(), 4096);
  LoggingDispatcher one, two, off;
  gpu().submit_now([&](VkCommandBuffer cb) {
    sort.record(cb, one, k.address(), v.address(), 410, 17);
    sort.record(cb, two, k.address(), v.address(), 2049, 17);
    sort.set_one_tile(false);
    sort.record(cb, off, k.address(), v.address(), 410, 17);
  });
  EXPECT_EQ(one.log, (std::vector<std::pair<std::string, uint32_t>>{{"radix_sort_tile", 1u}}));
  EXPECT_EQ(two.log.size(), 5u * 3 + 1);
  EXPECT_EQ(off.log.size(), 5u * 3 + 1);
}

TEST_F(Sort, RejectsBadArguments) {
  gpu::RadixSort sort(gpu(), 100);
  gpu::DirectDispatcher disp;
  EXPECT_THROW(sort.record(VK_NULL_HANDLE, disp, 0, 0, 101, 32), std::invalid_argument);
  EXPECT_THROW(sort.record(VK_NULL_HANDLE, disp, 0, 0, 10, 33), std::invalid_argument);
}

}  // namespace wetdem::test
