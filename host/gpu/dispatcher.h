// How a recorded pass sequence issues its dispatches. The system records the neighbour-list rebuild
// into every step but gates it: a GatedDispatcher turns each dispatch into an indirect one whose size the
// GPU sets to zero when no rebuild is due. Components (sort, scan) take a Dispatcher and do not care which.
#pragma once

#include <vulkan/vulkan.h>

#include <cstdint>

#include "vk/kernel.h"

namespace wetdem::gpu {

class Dispatcher {
 public:
  virtual ~Dispatcher() = default;
  // Records `k` over `groups` workgroups with the given push constants. The caller inserts barriers.
  virtual void dispatch(VkCommandBuffer cb, const vk::Kernel& k, uint32_t groups, const void* push,
                        uint32_t push_bytes) = 0;
};

class DirectDispatcher final : public Dispatcher {
 public:
  void dispatch(VkCommandBuffer cb, const vk::Kernel& k, uint32_t groups, const void* push,
                uint32_t push_bytes) override {
    k.dispatch(cb, groups, push, push_bytes);
  }
};

}  // namespace wetdem::gpu
