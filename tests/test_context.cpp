#include <gtest/gtest.h>

#include "support/gpu.h"
#include "vk/buffer.h"

namespace wetdem::test {

class Context : public GpuTest {};

TEST_F(Context, BufferRoundTripIsExact) {
  std::vector<uint32_t> in(1000);
  for (size_t i = 0; i < in.size(); ++i) in[i] = uint32_t(i * 2654435761u);
  vk::Buffer b(gpu(), in.size() * 4);
  b.upload(in);
  EXPECT_EQ(b.download_as<uint32_t>(in.size()), in);
  EXPECT_NE(b.address(), 0u);
}

TEST_F(Context, ValidationLayerIsOnInTests) {
  // ctest sets WETDEM_VALIDATION=1: the tests must run with the Khronos layer catching errors.
  EXPECT_TRUE(gpu().validation_enabled());
}

}  // namespace wetdem::test

#include "vk/kernel.h"

namespace wetdem::test {

TEST_F(Context, EmbeddedShaderRunsThroughDeviceAddresses) {
  vk::Kernel fill(gpu(), "fill_u32");
  vk::Buffer b(gpu(), 1000 * 4);
  struct {
    uint64_t dst;
    uint32_t n, value;
  } pc{b.address(), 999, 0xdeadbeefu};
  gpu().submit_now([&](VkCommandBuffer cb) { fill.dispatch(cb, 4, &pc, sizeof(pc)); });
  auto out = b.download_as<uint32_t>(1000);
  for (size_t i = 0; i < 999; ++i) ASSERT_EQ(out[i], 0xdeadbeefu) << i;
  EXPECT_EQ(out[999], 0u);  // n bounds the write
}

}  // namespace wetdem::test
