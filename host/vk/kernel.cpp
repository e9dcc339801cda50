#include "vk/kernel.h"

#include <fmt/core.h>

#include <cstring>

#include "wetdem_spirv/registry.h"

namespace wetdem::vk {

Kernel::Kernel(Context& ctx, const std::string& name, const std::vector<uint32_t>& spec)
    : ctx_(ctx), name_(name) {
  const spirv::Blob* blob = nullptr;
  for (const auto& b : spirv::kAll)
    if (name == b.name) blob = &b;
  if (!blob) throw std::runtime_error(fmt::format("no embedded shader named '{}'", name));
  VkShaderModuleCreateInfo mi{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
  mi.codeSize = blob->words * sizeof(uint32_t);
  mi.pCode = blob->code;
  WETDEM_VK(vkCreateShaderModule(ctx.device(), &mi, nullptr, &module_));
  layout_ = ctx.pipeline_layout();
  std::vector<VkSpecializationMapEntry> entries(spec.size());
  for (uint32_t k = 0; k < spec.size(); ++k) entries[k] = {k, k * 4, 4};
  VkSpecializationInfo si{uint32_t(entries.size()), entries.data(), spec.size() * 4, spec.data()};
  VkComputePipelineCreateInfo ci{VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO};
  ci.stage.sType = VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO;
  ci.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
  ci.stage.module = module_;
  ci.stage.pName = "main";
  ci.stage.pSpecializationInfo = spec.empty() ? nullptr : &si;
  ci.layout = layout_;
  WETDEM_VK(vkCreateComputePipelines(ctx.device(), VK_NULL_HANDLE, 1, &ci, nullptr, &pipeline_));
}

Kernel::~Kernel() {
  vkDestroyPipeline(ctx_.device(), pipeline_, nullptr);
  vkDestroyShaderModule(ctx_.device(), module_, nullptr);
}

namespace {
void push_all(VkCommandBuffer cb, VkPipelineLayout layout, const void* push, uint32_t bytes) {
  // Always push the full range so that no push-constant byte a shader declares is left undefined.
  uint8_t buf[kPushBytes] = {};
  if (bytes > kPushBytes) throw std::runtime_error("push constants exceed 128 bytes");
  if (push) std::memcpy(buf, push, bytes);
  vkCmdPushConstants(cb, layout, VK_SHADER_STAGE_COMPUTE_BIT, 0, kPushBytes, buf);
}
}  // namespace

void Kernel::dispatch(VkCommandBuffer cb, uint32_t groups, const void* push, uint32_t push_bytes) const {
  if (groups == 0) return;
  vkCmdBindPipeline(cb, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline_);
  push_all(cb, layout_, push, push_bytes);
  vkCmdDispatch(cb, groups, 1, 1);
}

void Kernel::dispatch_indirect(VkCommandBuffer cb, VkBuffer args, VkDeviceSize offset, const void* push,
                               uint32_t push_bytes) const {
  vkCmdBindPipeline(cb, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline_);
  push_all(cb, layout_, push, push_bytes);
  vkCmdDispatchIndirect(cb, args, offset);
}

void barrier(VkCommandBuffer cb) {
  VkMemoryBarrier mb{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
  mb.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT;
  mb.dstAccessMask = VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT |
                     VK_ACCESS_INDIRECT_COMMAND_READ_BIT | VK_ACCESS_TRANSFER_READ_BIT |
                     VK_ACCESS_TRANSFER_WRITE_BIT;
  vkCmdPipelineBarrier(cb, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
                       VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_DRAW_INDIRECT_BIT |
                           VK_PIPELINE_STAGE_TRANSFER_BIT,
                       0, 1, &mb, 0, nullptr, 0, nullptr);
}

}  // namespace wetdem::vk
