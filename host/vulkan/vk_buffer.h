// A buffer and its memory. Host-visible coherent memory when the device has a type
// that allows the buffer (lavapipe and most GPUs: always); otherwise device-local
// memory reached through a temporary staging buffer.
#pragma once
#include "host/vulkan/vk_context.h"
#include <cstddef>

namespace masq::vk {

class Buffer {
 public:
  Buffer() = default;
  // size 0 is raised to 16 bytes (a valid dummy binding). With
  // VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT the memory is allocated with device address.
  Buffer(Context& ctx, VkDeviceSize size, VkBufferUsageFlags usage);
  ~Buffer();
  Buffer(Buffer&& o) noexcept;
  Buffer& operator=(Buffer&& o) noexcept;
  Buffer(const Buffer&) = delete;
  Buffer& operator=(const Buffer&) = delete;

  void upload(const void* src, std::size_t bytes, std::size_t offset = 0);
  void download(void* dst, std::size_t bytes, std::size_t offset = 0) const;

  VkBuffer handle() const { return buffer_; }
  VkDeviceSize size() const { return size_; }
  VkDeviceAddress address() const; // requires the device-address usage
  bool valid() const { return buffer_ != VK_NULL_HANDLE; }

 private:
  void release() noexcept;
  void staged_copy(bool to_device, void* host, std::size_t bytes, std::size_t offset) const;
  Context* ctx_ = nullptr;
  VkBuffer buffer_ = VK_NULL_HANDLE;
  VkDeviceMemory memory_ = VK_NULL_HANDLE;
  VkDeviceSize size_ = 0;
  void* mapped_ = nullptr; // null: device-local, use staging
  VkBufferUsageFlags usage_ = 0;
};

} // namespace masq::vk
