// Device-local storage buffer reached by its device address, with staged upload/download.
#pragma once

#include <vulkan/vulkan.h>

#include <cstdint>
#include <vector>

#include "vk/context.h"

namespace wetdem::vk {

class Buffer {
 public:
  Buffer() = default;
  Buffer(Context& ctx, VkDeviceSize bytes);
  ~Buffer();
  Buffer(Buffer&& o) noexcept;
  Buffer& operator=(Buffer&& o) noexcept;
  Buffer(const Buffer&) = delete;
  Buffer& operator=(const Buffer&) = delete;

  VkBuffer handle() const { return buf_; }
  VkDeviceSize size() const { return size_; }
  uint64_t address() const { return addr_; }
  explicit operator bool() const { return buf_ != VK_NULL_HANDLE; }

  void upload(const void* data, VkDeviceSize bytes, VkDeviceSize offset = 0);
  void download(void* data, VkDeviceSize bytes, VkDeviceSize offset = 0) const;
  template <class T>
  void upload(const std::vector<T>& v) {
    upload(v.data(), v.size() * sizeof(T));
  }
  template <class T>
  std::vector<T> download_as(size_t count) const {
    std::vector<T> v(count);
    download(v.data(), count * sizeof(T));
    return v;
  }
  void zero();
  void fill(uint32_t word);  // every 4-byte word of the buffer

 private:
  void release();
  Context* ctx_ = nullptr;
  VkBuffer buf_ = VK_NULL_HANDLE;
  VkDeviceMemory mem_ = VK_NULL_HANDLE;
  VkDeviceSize size_ = 0;
  VkDeviceSize allocated_ = 0;  // the allocation's size (>= size_), counted in Context::device_bytes()
  uint64_t addr_ = 0;
};

// A host-visible buffer for transfers.
class Staging {
 public:
  Staging(Context& ctx, VkDeviceSize bytes);
  ~Staging();
  Staging(const Staging&) = delete;
  Staging& operator=(const Staging&) = delete;
  VkBuffer handle() const { return buf_; }
  void* map() const { return ptr_; }

 private:
  Context* ctx_;
  VkBuffer buf_ = VK_NULL_HANDLE;
  VkDeviceMemory mem_ = VK_NULL_HANDLE;
  void* ptr_ = nullptr;
};

}  // namespace wetdem::vk
