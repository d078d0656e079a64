#include "host/vulkan/vk_staging.h"
#include "host/limit_knob.h"
#include "host/vulkan/vk_barriers.h"
#include <algorithm>
#include <cstring>

namespace masq::vk {
namespace {

constexpr std::uint64_t kStagingCap = 64ull << 20;   // a few ms of PCIe per piece
constexpr std::uint64_t kStagingMinimum = 1ull << 20; // small uploads share one size

} // namespace

std::uint64_t Staging::piece_limit() const {
  std::uint64_t cap = lowered_limit("vulkan", kStagingCap, Knob::VkStagingBytes);
  return std::min<std::uint64_t>(cap, ctx_.max_allocation());
}

VkDeviceSize Staging::capacity() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return buffer_.valid() ? buffer_.size() : 0;
}

void Staging::reserve(std::size_t bytes) {
  if (buffer_.valid() && buffer_.size() >= bytes) return;
  std::uint64_t want = kStagingMinimum;
  while (want < bytes) want *= 2;
  want = std::max<std::uint64_t>(std::min<std::uint64_t>(want, piece_limit()), bytes);
  buffer_ = Buffer(); // the old one first: both need not exist at once
  buffer_ = Buffer(ctx_, want, 0, BufferRole::Staging);
  if (!buffer_.mapped()) throw Error("vulkan: the staging buffer is not host-visible");
}

void Staging::upload(const Buffer& dst, const void* src, std::size_t bytes, std::size_t offset) {
  std::lock_guard<std::mutex> lock(mutex_);
  const std::size_t piece = static_cast<std::size_t>(std::min<std::uint64_t>(bytes, piece_limit()));
  reserve(piece);
  for (std::size_t done = 0; done < bytes; done += piece) {
    const std::size_t n = std::min(piece, bytes - done);
    std::memcpy(buffer_.mapped_, static_cast<const char*>(src) + done, n);
    buffer_.flush(0, n); // host writes before the submission that reads them
    VkCommandBuffer cmd = ctx_.begin_commands();
    barrier_before_copy(ctx_, cmd);
    VkBufferCopy region{0, offset + done, n};
    vkCmdCopyBuffer(cmd, buffer_.handle(), dst.handle(), 1, &region);
    barrier_after_upload(ctx_, cmd);
    ctx_.submit_and_wait(cmd);
  }
}

void Staging::download(const Buffer& src, void* dst, std::size_t bytes, std::size_t offset) {
  std::lock_guard<std::mutex> lock(mutex_);
  const std::size_t piece = static_cast<std::size_t>(std::min<std::uint64_t>(bytes, piece_limit()));
  reserve(piece);
  for (std::size_t done = 0; done < bytes; done += piece) {
    const std::size_t n = std::min(piece, bytes - done);
    VkCommandBuffer cmd = ctx_.begin_commands();
    barrier_before_copy(ctx_, cmd);
    VkBufferCopy region{offset + done, 0, n};
    vkCmdCopyBuffer(cmd, src.handle(), buffer_.handle(), 1, &region);
    barrier_after_readback(ctx_, cmd);
    ctx_.submit_and_wait(cmd);
    buffer_.invalidate(0, n);
    std::memcpy(static_cast<char*>(dst) + done, buffer_.mapped_, n);
  }
}

} // namespace masq::vk
