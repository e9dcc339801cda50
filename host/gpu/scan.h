// Exclusive prefix sum of uint32 values in place at a device address (multi-level reduce-then-scan).
#pragma once

#include <vulkan/vulkan.h>

#include <cstdint>
#include <vector>

#include "gpu/dispatcher.h"
#include "vk/buffer.h"
#include "vk/context.h"
#include "vk/kernel.h"

namespace wetdem::gpu {

class Scan {
 public:
  // Elements per workgroup block (256 invocations x 8): every level shrinks the problem by this factor.
  static constexpr uint32_t kBlock = 2048;
  // Largest supported max_n: the first level's group count must stay within the 65535 that every
  // Vulkan device allows.
  static constexpr uint32_t kMaxN = 65535u * kBlock;

  // Owns the block-sum buffers of every level for up to max_n elements.
  Scan(vk::Context& ctx, uint32_t max_n);

  // Records data[i] <- sum(data[0..i)) for i < n, in place, and *total <- sum(data[0..n)) unless
  // total_addr is 0 (0 is written when n == 0). Wrapping uint32 arithmetic. Dispatch sizes depend only
  // on n. Inserts vk::barrier(cb) between its passes and after the last one. Throws if n > max_n.
  void record(VkCommandBuffer cb, Dispatcher& disp, uint64_t data_addr, uint32_t n, uint64_t total_addr);

  uint32_t max_n() const { return max_n_; }

 private:
  void record_level(VkCommandBuffer cb, Dispatcher& disp, size_t level, uint64_t data_addr, uint32_t n,
                    uint64_t total_addr);
  uint32_t max_n_;
  vk::Kernel reduce_, block_;
  std::vector<vk::Buffer> sums_;  // sums_[l]: block sums of level l (level 0 = the caller's data)
};

}  // namespace wetdem::gpu
