// The driver's own acceleration structures (VK_KHR_acceleration_structure): bottom
// levels of opaque triangles or procedural AABBs, and a top level over instances. Each
// build runs on the device and is waited for; inputs may be freed afterwards.
#pragma once
#include "host/vulkan/vk_buffer.h"
#include <span>

namespace masq::vk {

class AccelStructure {
 public:
  AccelStructure() = default;
  ~AccelStructure();
  AccelStructure(AccelStructure&& o) noexcept;
  AccelStructure& operator=(AccelStructure&& o) noexcept;
  AccelStructure(const AccelStructure&) = delete;
  AccelStructure& operator=(const AccelStructure&) = delete;

  VkAccelerationStructureKHR handle() const { return handle_; }
  VkDeviceAddress address() const { return address_; }
  std::size_t bytes() const { return static_cast<std::size_t>(storage_.size()); }

 private:
  friend AccelStructure build_accel(Context&, VkAccelerationStructureTypeKHR,
                                    const VkAccelerationStructureGeometryKHR&, std::uint32_t);
  void release() noexcept;
  Context* ctx_ = nullptr;
  Buffer storage_;
  VkAccelerationStructureKHR handle_ = VK_NULL_HANDLE;
  VkDeviceAddress address_ = 0;
};

// One geometry, `count` primitives (triangles or AABBs) or instances.
AccelStructure build_accel(Context& ctx, VkAccelerationStructureTypeKHR type,
                           const VkAccelerationStructureGeometryKHR& geometry, std::uint32_t count);

// Non-indexed triangles: 9 floats (3 vertices) per triangle, in submission order.
AccelStructure build_triangle_blas(Context& ctx, std::span<const float> vertices);
AccelStructure build_aabb_blas(Context& ctx, std::span<const VkAabbPositionsKHR> boxes);
AccelStructure build_tlas(Context& ctx, std::span<const VkAccelerationStructureInstanceKHR> instances);

} // namespace masq::vk
