// A compute pipeline built from an embedded SPIR-V blob. Buffers are reached through device addresses: push
// constants (at most 128 bytes, the guaranteed minimum) and, for the GPU system's kernels, the buffer table
// and parameters as uniform buffers in descriptor set 0 (the context's pipeline layout).
#pragma once

#include <vulkan/vulkan.h>

#include <cstdint>
#include <string>
#include <vector>

#include "vk/context.h"

namespace wetdem::vk {

inline constexpr uint32_t kPushBytes = kPushConstantBytes;

class Kernel {
 public:
  // spec: values of the shader's specialization constants 0, 1, ... (uint32), if any.
  Kernel(Context& ctx, const std::string& name, const std::vector<uint32_t>& spec = {});
  ~Kernel();
  Kernel(const Kernel&) = delete;
  Kernel& operator=(const Kernel&) = delete;

  const std::string& name() const { return name_; }
  // Records a dispatch of `groups` workgroups with the push-constant bytes `push` (size <= kPushBytes).
  void dispatch(VkCommandBuffer cb, uint32_t groups, const void* push, uint32_t push_bytes) const;
  // Records an indirect dispatch reading VkDispatchIndirectCommand at (buffer, offset).
  void dispatch_indirect(VkCommandBuffer cb, VkBuffer args, VkDeviceSize offset, const void* push,
                         uint32_t push_bytes) const;

 private:
  Context& ctx_;
  std::string name_;
  VkShaderModule module_ = VK_NULL_HANDLE;
  VkPipelineLayout layout_ = VK_NULL_HANDLE;  // the context's
  VkPipeline pipeline_ = VK_NULL_HANDLE;
};

// Full compute->compute (+indirect, +transfer) memory barrier: every pass sees the previous pass's writes.
void barrier(VkCommandBuffer cb);

}  // namespace wetdem::vk
