#include "host/vulkan/acceleration_structures.h"
#include <cstring>
#include <utility>

namespace masq::vk {
namespace {

template <class T>
AccelInput input_of(VkAccelerationStructureTypeKHR type, VkGeometryTypeKHR geometry, std::span<const T> items,
                    std::size_t count) {
  AccelInput in;
  in.type = type;
  in.geometry = geometry;
  in.data.resize(items.size_bytes());
  if (!items.empty()) std::memcpy(in.data.data(), items.data(), items.size_bytes());
  in.count = static_cast<std::uint32_t>(count);
  return in;
}

} // namespace

AccelStructure::~AccelStructure() { release(); }

AccelStructure::AccelStructure(AccelStructure&& o) noexcept { *this = std::move(o); }

AccelStructure& AccelStructure::operator=(AccelStructure&& o) noexcept {
  if (this != &o) {
    release(); // this structure goes before its block, then it takes the other's
    block_ = std::move(o.block_);
    handle_ = std::move(o.handle_);
    address_ = std::exchange(o.address_, 0);
    bytes_ = std::exchange(o.bytes_, 0);
  }
  return *this;
}

void AccelStructure::release() noexcept {
  handle_.reset();
  block_.reset(); // the block goes with its last structure
  bytes_ = 0;
}

AccelInput triangle_input(std::span<const float> vertices) {
  return input_of(VK_ACCELERATION_STRUCTURE_TYPE_BOTTOM_LEVEL_KHR, VK_GEOMETRY_TYPE_TRIANGLES_KHR, vertices,
                  vertices.size() / 9);
}

AccelInput aabb_input(std::span<const VkAabbPositionsKHR> boxes) {
  return input_of(VK_ACCELERATION_STRUCTURE_TYPE_BOTTOM_LEVEL_KHR, VK_GEOMETRY_TYPE_AABBS_KHR, boxes, boxes.size());
}

AccelInput instance_input(std::span<const VkAccelerationStructureInstanceKHR> instances) {
  return input_of(VK_ACCELERATION_STRUCTURE_TYPE_TOP_LEVEL_KHR, VK_GEOMETRY_TYPE_INSTANCES_KHR, instances,
                  instances.size());
}

} // namespace masq::vk
