// Vulkan instance, device and queue: chosen once, shared by every system and test.
#pragma once

#include <vulkan/vulkan.h>

#include <atomic>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace wetdem::vk {

inline constexpr uint32_t kPushConstantBytes =
    128;  // push constants of every kernel (the guaranteed minimum)

// Throws std::runtime_error naming the call when a Vulkan call fails.
void check(VkResult r, const char* what);
#define WETDEM_VK(call) ::wetdem::vk::check((call), #call)

struct ContextOptions {
  // Device choice: empty = $WETDEM_DEVICE, else best real GPU, else lavapipe. Accepts an index into the
  // enumerated devices, "cpu"/"lavapipe"/"gpu", or a case-insensitive substring of the device name.
  std::string device;
  // Khronos validation layer; also switched on by WETDEM_VALIDATION=1. Every validation error is counted
  // and printed; tests fail on a non-zero count.
  bool validation = false;
  bool quiet = false;  // do not print the chosen device
};

struct DeviceInfo {
  std::string name, driver_name, driver_info;
  VkPhysicalDeviceType type;
  uint32_t subgroup_size;
  double timestamp_period_ns;
  bool timestamps;
  bool int64_atomics = false;    // shaderBufferInt64Atomics (enabled when supported)
  std::string describe() const;  // "NAME (driver DRIVER INFO, type)"
};

class Context {
 public:
  explicit Context(const ContextOptions& opt = {});
  ~Context();
  Context(const Context&) = delete;
  Context& operator=(const Context&) = delete;

  VkDevice device() const { return device_; }
  VkPhysicalDevice physical() const { return phys_; }
  VkQueue queue() const { return queue_; }
  uint32_t queue_family() const { return family_; }
  VkCommandPool pool() const { return pool_; }
  // The pipeline layout of every kernel: kPushConstantBytes of push constants and descriptor set 0 (two
  // uniform buffers: the buffer table and the parameters), see context.cpp.
  VkPipelineLayout pipeline_layout() const { return pipeline_layout_; }
  VkDescriptorSetLayout set_layout() const { return set_layout_; }
  const DeviceInfo& info() const { return info_; }
  uint64_t validation_errors() const { return validation_errors_.load(); }
  bool validation_enabled() const { return messenger_ != VK_NULL_HANDLE; }

  uint32_t memory_type(uint32_t type_bits, VkMemoryPropertyFlags want) const;

  // Device-local bytes held by the live vk::Buffers of this context (their allocation sizes; benchmarks).
  uint64_t device_bytes() const { return device_bytes_.load(); }
  void account_device_bytes(int64_t delta) { device_bytes_ += uint64_t(delta); }

  // One-shot command buffer: record with fn, submit, wait.
  template <class Fn>
  void submit_now(Fn&& fn) {
    VkCommandBuffer cb = begin_one_shot();
    fn(cb);
    end_one_shot(cb);
  }
  VkCommandBuffer begin_one_shot();
  void end_one_shot(VkCommandBuffer cb);

  // Lists every physical device as "index: name (type)" for --list-devices.
  static std::vector<std::string> list_devices();

 private:
  static VkBool32 VKAPI_PTR on_message(VkDebugUtilsMessageSeverityFlagBitsEXT sev,
                                       VkDebugUtilsMessageTypeFlagsEXT type,
                                       const VkDebugUtilsMessengerCallbackDataEXT* data, void* user);
  VkInstance instance_ = VK_NULL_HANDLE;
  VkDebugUtilsMessengerEXT messenger_ = VK_NULL_HANDLE;
  VkPhysicalDevice phys_ = VK_NULL_HANDLE;
  VkDevice device_ = VK_NULL_HANDLE;
  VkQueue queue_ = VK_NULL_HANDLE;
  uint32_t family_ = 0;
  VkCommandPool pool_ = VK_NULL_HANDLE;
  VkFence fence_ = VK_NULL_HANDLE;
  VkDescriptorSetLayout set_layout_ = VK_NULL_HANDLE;
  VkPipelineLayout pipeline_layout_ = VK_NULL_HANDLE;
  DeviceInfo info_{};
  VkPhysicalDeviceMemoryProperties mem_{};
  std::atomic<uint64_t> validation_errors_{0};
  std::atomic<uint64_t> device_bytes_{0};
};

}  // namespace wetdem::vk
