#include "vk/buffer.h"

#include <cstring>
#include <string>
#include <utility>

namespace wetdem::vk {

namespace {
VkDeviceSize make_buffer(Context& ctx, VkDeviceSize bytes, VkBufferUsageFlags usage,
                         VkMemoryPropertyFlags props, bool address, VkBuffer& buf, VkDeviceMemory& mem) {
  VkBufferCreateInfo bi{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
  bi.size = bytes;
  bi.usage = usage;
  bi.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
  VkResult r = vkCreateBuffer(ctx.device(), &bi, nullptr, &buf);
  if (r != VK_SUCCESS)
    throw std::runtime_error("cannot create a Vulkan buffer of " + std::to_string(bytes) +
                             " bytes (VkResult " + std::to_string(int(r)) + ")");
  VkMemoryRequirements req;
  vkGetBufferMemoryRequirements(ctx.device(), buf, &req);
  VkMemoryAllocateFlagsInfo fi{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_FLAGS_INFO};
  fi.flags = VK_MEMORY_ALLOCATE_DEVICE_ADDRESS_BIT;
  VkMemoryAllocateInfo ai{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
  ai.pNext = address ? &fi : nullptr;
  ai.allocationSize = req.size;
  ai.memoryTypeIndex = ctx.memory_type(req.memoryTypeBits, props);
  WETDEM_VK(vkAllocateMemory(ctx.device(), &ai, nullptr, &mem));
  WETDEM_VK(vkBindBufferMemory(ctx.device(), buf, mem, 0));
  return req.size;
}
}  // namespace

Buffer::Buffer(Context& ctx, VkDeviceSize bytes) : ctx_(&ctx), size_(bytes) {
  if (bytes == 0) bytes = size_ = 16;
  allocated_ =
      make_buffer(ctx, bytes,
                  VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT |
                      VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT |
                      VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT | VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT,
                  VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT, true, buf_, mem_);
  ctx.account_device_bytes(int64_t(allocated_));
  VkBufferDeviceAddressInfo ai{VK_STRUCTURE_TYPE_BUFFER_DEVICE_ADDRESS_INFO};
  ai.buffer = buf_;
  addr_ = vkGetBufferDeviceAddress(ctx.device(), &ai);
  zero();
}

Buffer::~Buffer() {
  release();
}

void Buffer::release() {
  if (buf_) {
    vkDestroyBuffer(ctx_->device(), buf_, nullptr);
    vkFreeMemory(ctx_->device(), mem_, nullptr);
    ctx_->account_device_bytes(-int64_t(allocated_));
  }
  allocated_ = 0;
  buf_ = VK_NULL_HANDLE;
  mem_ = VK_NULL_HANDLE;
}

Buffer::Buffer(Buffer&& o) noexcept {
  *this = std::move(o);
}

Buffer& Buffer::operator=(Buffer&& o) noexcept {
  if (this != &o) {
    release();
    ctx_ = o.ctx_;
    buf_ = std::exchange(o.buf_, VK_NULL_HANDLE);
    mem_ = std::exchange(o.mem_, VK_NULL_HANDLE);
    size_ = std::exchange(o.size_, 0);
    allocated_ = std::exchange(o.allocated_, 0);
    addr_ = std::exchange(o.addr_, 0);
  }
  return *this;
}

void Buffer::upload(const void* data, VkDeviceSize bytes, VkDeviceSize offset) {
  if (bytes == 0) return;
  if (offset + bytes > size_) throw std::runtime_error("Buffer::upload out of range");
  Staging st(*ctx_, bytes);
  std::memcpy(st.map(), data, bytes);
  ctx_->submit_now([&](VkCommandBuffer cb) {
    VkBufferCopy c{0, offset, bytes};
    vkCmdCopyBuffer(cb, st.handle(), buf_, 1, &c);
  });
}

void Buffer::download(void* data, VkDeviceSize bytes, VkDeviceSize offset) const {
  if (bytes == 0) return;
  if (offset + bytes > size_) throw std::runtime_error("Buffer::download out of range");
  Staging st(*ctx_, bytes);
  ctx_->submit_now([&](VkCommandBuffer cb) {
    VkBufferCopy c{offset, 0, bytes};
    vkCmdCopyBuffer(cb, buf_, st.handle(), 1, &c);
  });
  std::memcpy(data, st.map(), bytes);
}

void Buffer::zero() {
  fill(0u);
}

void Buffer::fill(uint32_t word) {
  ctx_->submit_now([&](VkCommandBuffer cb) { vkCmdFillBuffer(cb, buf_, 0, VK_WHOLE_SIZE, word); });
}

Staging::Staging(Context& ctx, VkDeviceSize bytes) : ctx_(&ctx) {
  make_buffer(ctx, bytes, VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
              VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT, false, buf_, mem_);
  WETDEM_VK(vkMapMemory(ctx.device(), mem_, 0, VK_WHOLE_SIZE, 0, &ptr_));
}

Staging::~Staging() {
  vkUnmapMemory(ctx_->device(), mem_);
  vkDestroyBuffer(ctx_->device(), buf_, nullptr);
  vkFreeMemory(ctx_->device(), mem_, nullptr);
}

}  // namespace wetdem::vk
