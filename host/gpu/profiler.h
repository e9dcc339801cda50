// Per-pass GPU timing for benchmarks: a timestamp before every profiled dispatch; the time between two
// marks is charged to the earlier mark's pass. Off unless SystemOptions::profile_passes.
#pragma once

#include <vulkan/vulkan.h>

#include <map>
#include <string>
#include <vector>

#include "vk/context.h"
#include "wetdem/system.h"

namespace wetdem::gpu {

class Profiler {
 public:
  explicit Profiler(vk::Context& ctx) : ctx_(ctx) {}
  ~Profiler();
  void begin(VkCommandBuffer cb);  // starts a command buffer's marks
  void mark(VkCommandBuffer cb, const std::string& pass);
  void end(VkCommandBuffer cb);
  void submitted(VkCommandBuffer cb) { last_ = cb; }
  void collect();  // after the submit completed: accumulate the last recorded command buffer's marks
  std::vector<PassTiming> timings() const;
  void reset() { acc_.clear(); }

 private:
  struct Recording {
    VkQueryPool pool = VK_NULL_HANDLE;
    std::vector<std::string> names;
  };
  void ensure_pool(Recording& r, uint32_t count);
  vk::Context& ctx_;
  std::map<VkCommandBuffer, Recording> rec_;
  VkCommandBuffer last_ = VK_NULL_HANDLE;
  std::map<std::string, PassTiming> acc_;
};

}  // namespace wetdem::gpu
