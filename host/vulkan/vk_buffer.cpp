#include "host/vulkan/vk_buffer.h"
#include "host/vulkan/vk_staging.h"
#include "masq/knobs.h"
#include <fmt/format.h>
#include <cstdlib>
#include <cstring>
#include <utility>

namespace masq::vk {
namespace {

// MASQ_VK_FORCE_STAGING=1: the discrete-GPU path on any device (only staging is mapped),
// so lavapipe runs the copies and barriers a GPU needs. Read per buffer, like the limit
// knobs, so that a test can set it before a context exists.
bool staging_forced() {
  return knob_flag(Knob::VkForceStaging, "vulkan");
}

} // namespace

Buffer::Buffer(Context& ctx, VkDeviceSize size, VkBufferUsageFlags usage)
    : Buffer(ctx, size, usage, default_role(usage)) {}

Buffer::Buffer(Context& ctx, VkDeviceSize size, VkBufferUsageFlags usage, BufferRole role)
    : ctx_(&ctx), memory_(ctx.device(), vkFreeMemory), buffer_(ctx.device(), vkDestroyBuffer), role_(role) {
  size_ = size < 16 ? 16 : size;
  VkBufferCreateInfo bci{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
  bci.size = size_;
  bci.usage = usage | VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT;
  bci.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
  MASQ_VK_CHECK(vkCreateBuffer(ctx.device(), &bci, nullptr, buffer_.put()));
  VkMemoryRequirements req{};
  vkGetBufferMemoryRequirements(ctx.device(), buffer_.get(), &req);
  placement_ = place_buffer(role, ctx.memory(), req.memoryTypeBits, staging_forced());
  VkMemoryAllocateFlagsInfo flags{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_FLAGS_INFO};
  flags.flags = VK_MEMORY_ALLOCATE_DEVICE_ADDRESS_BIT;
  VkMemoryAllocateInfo mai{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
  mai.pNext = (usage & VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT) ? &flags : nullptr;
  mai.allocationSize = req.size;
  mai.memoryTypeIndex = placement_.type_index;
  allocation_ = ctx.acquire_allocation(); // maxMemoryAllocationCount (vk_context.h)
  if (VkResult r = vkAllocateMemory(ctx.device(), &mai, nullptr, memory_.put()); r != VK_SUCCESS) {
    memory_.release();
    allocation_ = {};
    if (r != VK_ERROR_OUT_OF_DEVICE_MEMORY && r != VK_ERROR_OUT_OF_HOST_MEMORY)
      throw_vk_error("vkAllocateMemory", r, __FILE__, __LINE__);
    // Out of memory: name the heap and its size, the limit the caller ran into (the
    // caller adds which array it was).
    const std::uint32_t heap = ctx.memory().memoryTypes[placement_.type_index].heapIndex;
    throw Error(fmt::format("vulkan: vkAllocateMemory of {} bytes for {} failed: {} (memory type {}, heap {} of {} "
                            "bytes on '{}')",
                            req.size, role_name(role), result_name(r), placement_.type_index, heap,
                            ctx.memory().memoryHeaps[heap].size, ctx.props().deviceName));
  }
  allocation_size_ = req.size;
  MASQ_VK_CHECK(vkBindBufferMemory(ctx.device(), buffer_.get(), memory_.get(), 0));
  if (placement_.host == HostAccess::Mapped)
    MASQ_VK_CHECK(vkMapMemory(ctx.device(), memory_.get(), 0, VK_WHOLE_SIZE, 0, &mapped_));
}

Buffer::~Buffer() { release(); }

Buffer::Buffer(Buffer&& o) noexcept { *this = std::move(o); }

Buffer& Buffer::operator=(Buffer&& o) noexcept {
  if (this != &o) {
    release(); // this buffer's objects go before it takes the other's
    ctx_ = std::exchange(o.ctx_, nullptr);
    allocation_ = std::move(o.allocation_);
    memory_ = std::move(o.memory_);
    buffer_ = std::move(o.buffer_);
    size_ = std::exchange(o.size_, 0);
    allocation_size_ = std::exchange(o.allocation_size_, 0);
    mapped_ = std::exchange(o.mapped_, nullptr);
    role_ = o.role_;
    placement_ = o.placement_;
  }
  return *this;
}

void Buffer::release() noexcept {
  buffer_.reset();
  memory_.reset(); // unmaps implicitly
  allocation_ = {};
  mapped_ = nullptr;
}

void Buffer::flush(std::size_t offset, std::size_t bytes) const {
  if (!placement_.needs_flush_invalidate || bytes == 0) return;
  AtomRange r = atom_aligned_range(offset, bytes, ctx_->props().limits.nonCoherentAtomSize, allocation_size_);
  VkMappedMemoryRange range{VK_STRUCTURE_TYPE_MAPPED_MEMORY_RANGE, nullptr, memory_.get(), r.offset, r.size};
  MASQ_VK_CHECK(vkFlushMappedMemoryRanges(ctx_->device(), 1, &range));
}

void Buffer::invalidate(std::size_t offset, std::size_t bytes) const {
  if (!placement_.needs_flush_invalidate || bytes == 0) return;
  AtomRange r = atom_aligned_range(offset, bytes, ctx_->props().limits.nonCoherentAtomSize, allocation_size_);
  VkMappedMemoryRange range{VK_STRUCTURE_TYPE_MAPPED_MEMORY_RANGE, nullptr, memory_.get(), r.offset, r.size};
  MASQ_VK_CHECK(vkInvalidateMappedMemoryRanges(ctx_->device(), 1, &range));
}

void Buffer::upload(const void* src, std::size_t bytes, std::size_t offset) {
  if (bytes == 0) return;
  if (offset + bytes > size_) throw Error("vulkan: buffer upload out of range");
  if (mapped_) {
    std::memcpy(static_cast<char*>(mapped_) + offset, src, bytes);
    flush(offset, bytes); // vkQueueSubmit then makes the host writes visible to the device
  } else {
    ctx_->staging().upload(*this, src, bytes, offset);
  }
}

void Buffer::download(void* dst, std::size_t bytes, std::size_t offset) const {
  if (bytes == 0) return;
  if (offset + bytes > size_) throw Error("vulkan: buffer download out of range");
  if (mapped_) {
    invalidate(offset, bytes); // device writes were made available to the host by a barrier
    std::memcpy(dst, static_cast<const char*>(mapped_) + offset, bytes);
  } else {
    ctx_->staging().download(*this, dst, bytes, offset);
  }
}

VkDeviceAddress Buffer::address() const {
  VkBufferDeviceAddressInfo info{VK_STRUCTURE_TYPE_BUFFER_DEVICE_ADDRESS_INFO};
  info.buffer = buffer_.get();
  return vkGetBufferDeviceAddress(ctx_->device(), &info);
}

} // namespace masq::vk
