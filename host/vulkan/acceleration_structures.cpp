#include "host/vulkan/acceleration_structures.h"
#include <utility>

namespace masq::vk {
namespace {

constexpr VkBufferUsageFlags kInputUsage =
    VK_BUFFER_USAGE_ACCELERATION_STRUCTURE_BUILD_INPUT_READ_ONLY_BIT_KHR | VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT;

Buffer input_buffer(Context& ctx, const void* data, std::size_t bytes) {
  Buffer b(ctx, bytes, kInputUsage);
  b.upload(data, bytes);
  return b;
}

} // namespace

AccelStructure::~AccelStructure() { release(); }

AccelStructure::AccelStructure(AccelStructure&& o) noexcept { *this = std::move(o); }

AccelStructure& AccelStructure::operator=(AccelStructure&& o) noexcept {
  if (this != &o) {
    release();
    ctx_ = std::exchange(o.ctx_, nullptr);
    storage_ = std::move(o.storage_);
    handle_ = std::exchange(o.handle_, VK_NULL_HANDLE);
    address_ = std::exchange(o.address_, 0);
  }
  return *this;
}

void AccelStructure::release() noexcept {
  if (ctx_ && handle_) ctx_->accel.destroy(ctx_->device, handle_, nullptr);
  handle_ = VK_NULL_HANDLE;
  storage_ = Buffer();
}

AccelStructure build_accel(Context& ctx, VkAccelerationStructureTypeKHR type,
                           const VkAccelerationStructureGeometryKHR& geometry, std::uint32_t count) {
  VkAccelerationStructureBuildGeometryInfoKHR info{VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_BUILD_GEOMETRY_INFO_KHR};
  info.type = type;
  info.flags = VK_BUILD_ACCELERATION_STRUCTURE_PREFER_FAST_TRACE_BIT_KHR;
  info.mode = VK_BUILD_ACCELERATION_STRUCTURE_MODE_BUILD_KHR;
  info.geometryCount = 1;
  info.pGeometries = &geometry;
  VkAccelerationStructureBuildSizesInfoKHR sizes{VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_BUILD_SIZES_INFO_KHR};
  ctx.accel.build_sizes(ctx.device, VK_ACCELERATION_STRUCTURE_BUILD_TYPE_DEVICE_KHR, &info, &count, &sizes);

  AccelStructure as;
  as.ctx_ = &ctx;
  as.storage_ = Buffer(ctx, sizes.accelerationStructureSize,
                       VK_BUFFER_USAGE_ACCELERATION_STRUCTURE_STORAGE_BIT_KHR |
                           VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT);
  VkAccelerationStructureCreateInfoKHR ci{VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_CREATE_INFO_KHR};
  ci.buffer = as.storage_.handle();
  ci.size = sizes.accelerationStructureSize;
  ci.type = type;
  MASQ_VK_CHECK(ctx.accel.create(ctx.device, &ci, nullptr, &as.handle_));

  VkDeviceSize align = ctx.accel_props.minAccelerationStructureScratchOffsetAlignment;
  if (align == 0) align = 1;
  Buffer scratch(ctx, sizes.buildScratchSize + align,
                 VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT, BufferRole::AccelScratch);
  VkDeviceAddress scratch_addr = (scratch.address() + align - 1) / align * align;

  info.dstAccelerationStructure = as.handle_;
  info.scratchData.deviceAddress = scratch_addr;
  VkAccelerationStructureBuildRangeInfoKHR range{count, 0, 0, 0};
  const VkAccelerationStructureBuildRangeInfoKHR* ranges = &range;
  VkCommandBuffer cmd = ctx.begin_commands();
  ctx.accel.cmd_build(cmd, 1, &info, &ranges);
  // The build's writes must be visible to the next build (a TLAS over this BLAS) and
  // to ray queries; each build is its own submission, the barrier keeps it explicit.
  VkMemoryBarrier mb{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
  mb.srcAccessMask = VK_ACCESS_ACCELERATION_STRUCTURE_WRITE_BIT_KHR;
  mb.dstAccessMask = VK_ACCESS_ACCELERATION_STRUCTURE_READ_BIT_KHR;
  vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_ACCELERATION_STRUCTURE_BUILD_BIT_KHR,
                       VK_PIPELINE_STAGE_ACCELERATION_STRUCTURE_BUILD_BIT_KHR | VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                       0, 1, &mb, 0, nullptr, 0, nullptr);
  ctx.submit_and_wait(cmd);

  VkAccelerationStructureDeviceAddressInfoKHR ai{VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_DEVICE_ADDRESS_INFO_KHR};
  ai.accelerationStructure = as.handle_;
  as.address_ = ctx.accel.device_address(ctx.device, &ai);
  return as;
}

AccelStructure build_triangle_blas(Context& ctx, std::span<const float> vertices) {
  Buffer input = input_buffer(ctx, vertices.data(), vertices.size_bytes());
  VkAccelerationStructureGeometryKHR g{VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_GEOMETRY_KHR};
  g.geometryType = VK_GEOMETRY_TYPE_TRIANGLES_KHR;
  g.flags = VK_GEOMETRY_OPAQUE_BIT_KHR;
  auto& t = g.geometry.triangles;
  t.sType = VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_GEOMETRY_TRIANGLES_DATA_KHR;
  t.vertexFormat = VK_FORMAT_R32G32B32_SFLOAT;
  t.vertexData.deviceAddress = input.address();
  t.vertexStride = 3 * sizeof(float);
  t.maxVertex = static_cast<std::uint32_t>(vertices.size() / 3 == 0 ? 0 : vertices.size() / 3 - 1);
  t.indexType = VK_INDEX_TYPE_NONE_KHR;
  return build_accel(ctx, VK_ACCELERATION_STRUCTURE_TYPE_BOTTOM_LEVEL_KHR, g,
                     static_cast<std::uint32_t>(vertices.size() / 9));
}

AccelStructure build_aabb_blas(Context& ctx, std::span<const VkAabbPositionsKHR> boxes) {
  Buffer input = input_buffer(ctx, boxes.data(), boxes.size_bytes());
  VkAccelerationStructureGeometryKHR g{VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_GEOMETRY_KHR};
  g.geometryType = VK_GEOMETRY_TYPE_AABBS_KHR;
  g.flags = VK_GEOMETRY_OPAQUE_BIT_KHR; // candidates still reach the shader, which decides
  g.geometry.aabbs.sType = VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_GEOMETRY_AABBS_DATA_KHR;
  g.geometry.aabbs.data.deviceAddress = input.address();
  g.geometry.aabbs.stride = sizeof(VkAabbPositionsKHR);
  return build_accel(ctx, VK_ACCELERATION_STRUCTURE_TYPE_BOTTOM_LEVEL_KHR, g,
                     static_cast<std::uint32_t>(boxes.size()));
}

AccelStructure build_tlas(Context& ctx, std::span<const VkAccelerationStructureInstanceKHR> instances) {
  Buffer input = input_buffer(ctx, instances.data(), instances.size_bytes());
  VkAccelerationStructureGeometryKHR g{VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_GEOMETRY_KHR};
  g.geometryType = VK_GEOMETRY_TYPE_INSTANCES_KHR;
  g.geometry.instances.sType = VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_GEOMETRY_INSTANCES_DATA_KHR;
  g.geometry.instances.arrayOfPointers = VK_FALSE;
  g.geometry.instances.data.deviceAddress = input.address();
  return build_accel(ctx, VK_ACCELERATION_STRUCTURE_TYPE_TOP_LEVEL_KHR, g,
                     static_cast<std::uint32_t>(instances.size()));
}

} // namespace masq::vk
