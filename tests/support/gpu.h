// Shared Vulkan context for GPU tests (lavapipe, validation on via ctest's environment).
// GpuTest fails a test that produced validation errors.
#pragma once

#include <gtest/gtest.h>

#include "vk/context.h"

namespace wetdem::test {

vk::Context& gpu();

class GpuTest : public ::testing::Test {
 protected:
  void SetUp() override { errors_before_ = gpu().validation_errors(); }
  void TearDown() override {
    EXPECT_EQ(gpu().validation_errors(), errors_before_) << "Vulkan validation errors during this test";
  }

 private:
  uint64_t errors_before_ = 0;
};

}  // namespace wetdem::test
