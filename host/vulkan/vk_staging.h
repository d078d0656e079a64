// The persistent staging buffer of a Context: every copy between the host and device
// memory the host does not map goes through it. Created on first use, grown to the
// largest copy up to a cap (64 MiB, lowered by MASQ_VK_STAGING_BYTES), reused; a larger
// copy runs in pieces of the cap. Each piece is one submission that ends in a barrier
// making the transfer's writes visible to what reads them next (compute shaders,
// acceleration-structure builds, later copies, the host).
#pragma once
#include "host/vulkan/vk_buffer.h"
#include <cstddef>
#include <mutex>

namespace masq::vk {

class Staging {
 public:
  explicit Staging(Context& ctx) : ctx_(ctx) {}
  Staging(const Staging&) = delete;
  Staging& operator=(const Staging&) = delete;

  // Both wait for the device. Thread-safe: backends on several threads share a context.
  void upload(const Buffer& dst, const void* src, std::size_t bytes, std::size_t offset);
  void download(const Buffer& src, void* dst, std::size_t bytes, std::size_t offset);

  // The staging buffer's size now (0 before the first copy), for tests.
  VkDeviceSize capacity() const;
  // The largest piece one copy moves: 64 MiB, MASQ_VK_STAGING_BYTES, maxMemoryAllocationSize.
  std::uint64_t piece_limit() const;

 private:
  void reserve(std::size_t bytes); // caller holds mutex_
  Context& ctx_;
  mutable std::mutex mutex_;
  Buffer buffer_;
};

} // namespace masq::vk
