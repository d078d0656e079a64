#include "host/vulkan/vk_buffer.h"
#include <cstring>
#include <utility>

namespace masq::vk {
namespace {

int find_memory_type(const VkPhysicalDeviceMemoryProperties& mp, std::uint32_t allowed,
                     VkMemoryPropertyFlags want) {
  for (std::uint32_t i = 0; i < mp.memoryTypeCount; ++i)
    if ((allowed & (1u << i)) && (mp.memoryTypes[i].propertyFlags & want) == want)
      return static_cast<int>(i);
  return -1;
}

} // namespace

Buffer::Buffer(Context& ctx, VkDeviceSize size, VkBufferUsageFlags usage) : ctx_(&ctx), usage_(usage) {
  size_ = size < 16 ? 16 : size;
  VkBufferCreateInfo bci{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
  bci.size = size_;
  bci.usage = usage | VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT;
  bci.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
  MASQ_VK_CHECK(vkCreateBuffer(ctx.device, &bci, nullptr, &buffer_));
  try {
    VkMemoryRequirements req{};
    vkGetBufferMemoryRequirements(ctx.device, buffer_, &req);
    int type = find_memory_type(ctx.memory, req.memoryTypeBits,
                                VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT);
    bool host_visible = type >= 0;
    if (!host_visible) type = find_memory_type(ctx.memory, req.memoryTypeBits, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
    if (type < 0) type = find_memory_type(ctx.memory, req.memoryTypeBits, 0);
    if (type < 0) throw Error("vulkan: no memory type can hold a buffer");
    VkMemoryAllocateFlagsInfo flags{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_FLAGS_INFO};
    flags.flags = VK_MEMORY_ALLOCATE_DEVICE_ADDRESS_BIT;
    VkMemoryAllocateInfo mai{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
    mai.pNext = (usage & VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT) ? &flags : nullptr;
    mai.allocationSize = req.size;
    mai.memoryTypeIndex = static_cast<std::uint32_t>(type);
    ctx.acquire_allocation(); // maxMemoryAllocationCount (vk_context.h)
    if (VkResult r = vkAllocateMemory(ctx.device, &mai, nullptr, &memory_); r != VK_SUCCESS) {
      memory_ = VK_NULL_HANDLE;
      ctx.release_allocation();
      throw_vk_error("vkAllocateMemory", r, __FILE__, __LINE__);
    }
    MASQ_VK_CHECK(vkBindBufferMemory(ctx.device, buffer_, memory_, 0));
    if (host_visible) MASQ_VK_CHECK(vkMapMemory(ctx.device, memory_, 0, VK_WHOLE_SIZE, 0, &mapped_));
  } catch (...) {
    release();
    throw;
  }
}

Buffer::~Buffer() { release(); }

Buffer::Buffer(Buffer&& o) noexcept { *this = std::move(o); }

Buffer& Buffer::operator=(Buffer&& o) noexcept {
  if (this != &o) {
    release();
    ctx_ = std::exchange(o.ctx_, nullptr);
    buffer_ = std::exchange(o.buffer_, VK_NULL_HANDLE);
    memory_ = std::exchange(o.memory_, VK_NULL_HANDLE);
    size_ = std::exchange(o.size_, 0);
    mapped_ = std::exchange(o.mapped_, nullptr);
    usage_ = std::exchange(o.usage_, 0);
  }
  return *this;
}

void Buffer::release() noexcept {
  if (!ctx_) return;
  if (buffer_) vkDestroyBuffer(ctx_->device, buffer_, nullptr);
  if (memory_) {
    vkFreeMemory(ctx_->device, memory_, nullptr); // unmaps implicitly
    ctx_->release_allocation();
  }
  buffer_ = VK_NULL_HANDLE;
  memory_ = VK_NULL_HANDLE;
  mapped_ = nullptr;
}

void Buffer::upload(const void* src, std::size_t bytes, std::size_t offset) {
  if (bytes == 0) return;
  if (offset + bytes > size_) throw Error("vulkan: buffer upload out of range");
  if (mapped_) std::memcpy(static_cast<char*>(mapped_) + offset, src, bytes);
  else staged_copy(true, const_cast<void*>(src), bytes, offset);
}

void Buffer::download(void* dst, std::size_t bytes, std::size_t offset) const {
  if (bytes == 0) return;
  if (offset + bytes > size_) throw Error("vulkan: buffer download out of range");
  if (mapped_) std::memcpy(dst, static_cast<const char*>(mapped_) + offset, bytes);
  else staged_copy(false, dst, bytes, offset);
}

void Buffer::staged_copy(bool to_device, void* host, std::size_t bytes, std::size_t offset) const {
  Buffer staging(*ctx_, bytes, 0);
  if (!staging.mapped_) throw Error("vulkan: device has no host-visible memory for staging");
  if (to_device) std::memcpy(staging.mapped_, host, bytes);
  VkCommandBuffer cmd = ctx_->begin_commands();
  VkBufferCopy region{to_device ? 0 : offset, to_device ? offset : 0, bytes};
  if (to_device) vkCmdCopyBuffer(cmd, staging.buffer_, buffer_, 1, &region);
  else vkCmdCopyBuffer(cmd, buffer_, staging.buffer_, 1, &region);
  ctx_->submit_and_wait(cmd);
  if (!to_device) std::memcpy(host, staging.mapped_, bytes);
}

VkDeviceAddress Buffer::address() const {
  VkBufferDeviceAddressInfo info{VK_STRUCTURE_TYPE_BUFFER_DEVICE_ADDRESS_INFO};
  info.buffer = buffer_;
  return vkGetBufferDeviceAddress(ctx_->device, &info);
}

} // namespace masq::vk
