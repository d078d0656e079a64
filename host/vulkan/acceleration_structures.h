// The driver's own acceleration structures (VK_KHR_acceleration_structure): bottom
// levels of opaque triangles or procedural AABBs, and a top level over instances.
// build_accels builds many per command buffer and compacts the bottom levels
// (host/vulkan/accel_batch.cpp); inputs may be freed afterwards.
#pragma once
#include "host/vulkan/vk_buffer.h"
#include <cstddef>
#include <functional>
#include <memory>
#include <span>
#include <vector>

namespace masq::vk {

// A built structure (compacted when a bottom level) in a slice of a storage block it shares with the other
// structures of its build_accels call; the block lives while any of them does.
class AccelStructure {
 public:
  AccelStructure() = default;
  ~AccelStructure();
  AccelStructure(AccelStructure&& o) noexcept;
  AccelStructure& operator=(AccelStructure&& o) noexcept;
  AccelStructure(const AccelStructure&) = delete;
  AccelStructure& operator=(const AccelStructure&) = delete;

  VkAccelerationStructureKHR handle() const { return handle_.get(); }
  VkDeviceAddress address() const { return address_; }
  std::size_t bytes() const { return bytes_; } // its size on the device (a bottom level's compacted)

 private:
  friend class AccelBatch;
  void release() noexcept;
  std::shared_ptr<Buffer> block_;
  DeviceOwned<VkAccelerationStructureKHR> handle_; // goes before its block
  VkDeviceAddress address_ = 0;
  std::size_t bytes_ = 0;
};

// What the driver builds one structure from: one geometry of `count` primitives (or
// instances), its data as the driver reads it.
struct AccelInput {
  VkAccelerationStructureTypeKHR type = VK_ACCELERATION_STRUCTURE_TYPE_BOTTOM_LEVEL_KHR;
  VkGeometryTypeKHR geometry = VK_GEOMETRY_TYPE_AABBS_KHR;
  std::vector<std::byte> data;
  std::uint32_t count = 0;
};
// Non-indexed triangles: 9 floats (3 vertices) per triangle, in submission order.
AccelInput triangle_input(std::span<const float> vertices);
AccelInput aabb_input(std::span<const VkAabbPositionsKHR> boxes);
AccelInput instance_input(std::span<const VkAccelerationStructureInstanceKHR> instances);

// How large a batch of builds may grow: bytes of its one scratch buffer, of its one
// buffer of uncompacted structures and of its one input buffer (each), builds in it,
// and the size of the blocks the compacted structures are sub-allocated from. Each is
// also bounded by the largest allocation (Context::max_allocation_bytes); a single
// structure larger than a batch or a block gets a batch or a block of its own.
struct AccelBatchLimits {
  VkDeviceSize batch_bytes = VkDeviceSize{64} << 20;
  std::size_t batch_builds = 1024;
  VkDeviceSize block_bytes = VkDeviceSize{64} << 20;
};

// Builds `count` structures, input(i) giving the i-th (asked for once, in order), and
// returns them in that order. Per batch: one input, one scratch and one storage buffer,
// one command buffer holding every build (disjoint scratch regions, so no barrier
// between them) and a compacted-size query per bottom level, then one command buffer
// of compacting copies into the shared blocks. Top levels are built in place in the
// blocks, not compacted (accel_batch.cpp says why). Throws masq::Error naming
// `backend`, the structure and the limit when one needs more than one allocation holds.
std::vector<AccelStructure> build_accels(Context& ctx, const char* backend, std::size_t count,
                                         const std::function<AccelInput(std::size_t)>& input,
                                         const AccelBatchLimits& limits = {});

} // namespace masq::vk
