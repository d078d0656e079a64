// A buffer and its memory, placed by its role (host/vulkan/vk_memory_placement.h):
// device data in DEVICE_LOCAL memory, written in place only where a device-local heap
// is host-visible and large (resizable BAR, UMA, lavapipe), otherwise through the
// context's persistent staging buffer (host/vulkan/vk_staging.h); results in host-cached
// memory. Non-coherent mapped memory is flushed / invalidated on nonCoherentAtomSize.
#pragma once
#include "host/vulkan/vk_context.h"
#include "host/vulkan/vk_memory_placement.h"
#include <cstddef>

namespace masq::vk {

// v rounded up to a multiple of a (a > 0): buffer offsets and shader-binding-table strides.
inline VkDeviceSize align_up(VkDeviceSize v, VkDeviceSize a) { return (v + a - 1) / a * a; }

class Buffer {
 public:
  Buffer() = default;
  // size 0 is raised to 16 bytes (a valid dummy binding). With
  // VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT the memory is allocated with device address.
  // Without a role, default_role(usage) places it (storage buffers as scene data).
  Buffer(Context& ctx, VkDeviceSize size, VkBufferUsageFlags usage);
  Buffer(Context& ctx, VkDeviceSize size, VkBufferUsageFlags usage, BufferRole role);
  ~Buffer();
  Buffer(Buffer&& o) noexcept;
  Buffer& operator=(Buffer&& o) noexcept;
  Buffer(const Buffer&) = delete;
  Buffer& operator=(const Buffer&) = delete;

  // Both wait for the device: the data is in place (or back) when they return.
  void upload(const void* src, std::size_t bytes, std::size_t offset = 0);
  void download(void* dst, std::size_t bytes, std::size_t offset = 0) const;

  VkBuffer handle() const { return buffer_.get(); }
  VkDeviceSize size() const { return size_; }
  VkDeviceAddress address() const; // requires the device-address usage
  bool valid() const { return static_cast<bool>(buffer_); }
  BufferRole role() const { return role_; }
  const MemoryPlacement& placement() const { return placement_; }
  bool mapped() const { return mapped_ != nullptr; }

 private:
  friend class Staging; // writes and reads the staging buffer's mapping
  void release() noexcept;
  // Host writes to / device writes for a non-coherent mapping: flush / invalidate.
  void flush(std::size_t offset, std::size_t bytes) const;
  void invalidate(std::size_t offset, std::size_t bytes) const;
  Context* ctx_ = nullptr;
  // The buffer goes first, then its memory, then the memory's count.
  Context::Allocation allocation_;
  DeviceOwned<VkDeviceMemory> memory_;
  DeviceOwned<VkBuffer> buffer_;
  VkDeviceSize size_ = 0;
  VkDeviceSize allocation_size_ = 0;
  void* mapped_ = nullptr; // null: reached through the staging buffer
  BufferRole role_ = BufferRole::SceneData;
  MemoryPlacement placement_;
};

} // namespace masq::vk
