// build_accels (acceleration_structures.h): many structures per command buffer, one
// scratch buffer per batch, compacted into a few large storage blocks. A driver limits
// the live memory allocations of a device (maxMemoryAllocationCount, 4096 on many), so
// one allocation and one submit-and-wait per structure cannot hold a cluster scene's
// thousands of BLAS; compaction also gives the bytes the structures really need (the
// build sizes are the driver's worst case).
#include "host/vulkan/vk_buffer.h"
#include "host/vulkan/acceleration_structures.h"
#include "host/vulkan/vk_barriers.h"
#include <fmt/format.h>
#include <algorithm>

namespace masq::vk {
namespace {

constexpr VkDeviceSize kStorageAlign = 256; // VkAccelerationStructureCreateInfoKHR::offset
constexpr VkDeviceSize kInputAlign = 16;    // instances need 16, AABBs 8, vertices 4
constexpr VkBufferUsageFlags kStorageUsage =
    VK_BUFFER_USAGE_ACCELERATION_STRUCTURE_STORAGE_BIT_KHR | VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT;


VkAccelerationStructureGeometryKHR geometry_of(const AccelInput& in, VkDeviceAddress data) {
  VkAccelerationStructureGeometryKHR g{VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_GEOMETRY_KHR};
  g.geometryType = in.geometry;
  if (in.geometry == VK_GEOMETRY_TYPE_TRIANGLES_KHR) {
    // One any-hit call per candidate: rtpipeline counts the calls (kernels/rt_shared.h).
    g.flags = VK_GEOMETRY_OPAQUE_BIT_KHR | VK_GEOMETRY_NO_DUPLICATE_ANY_HIT_INVOCATION_BIT_KHR;
    auto& t = g.geometry.triangles;
    t.sType = VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_GEOMETRY_TRIANGLES_DATA_KHR;
    t.vertexFormat = VK_FORMAT_R32G32B32_SFLOAT;
    t.vertexData.deviceAddress = data;
    t.vertexStride = 3 * sizeof(float);
    t.maxVertex = in.count == 0 ? 0 : 3 * in.count - 1;
    t.indexType = VK_INDEX_TYPE_NONE_KHR;
  } else if (in.geometry == VK_GEOMETRY_TYPE_AABBS_KHR) {
    // Candidates still reach the shader, which decides; one intersection call each.
    g.flags = VK_GEOMETRY_OPAQUE_BIT_KHR | VK_GEOMETRY_NO_DUPLICATE_ANY_HIT_INVOCATION_BIT_KHR;
    g.geometry.aabbs.sType = VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_GEOMETRY_AABBS_DATA_KHR;
    g.geometry.aabbs.data.deviceAddress = data;
    g.geometry.aabbs.stride = sizeof(VkAabbPositionsKHR);
  } else {
    g.geometry.instances.sType = VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_GEOMETRY_INSTANCES_DATA_KHR;
    g.geometry.instances.arrayOfPointers = VK_FALSE;
    g.geometry.instances.data.deviceAddress = data;
  }
  return g;
}

// Bottom levels are compacted; a top level is built in place: its instances leave
// the driver little to compact, it is rebuilt whole when robust masquerade widens its
// boxes, and on lavapipe the copy of a 144K-instance TLAS cost more than the build
// gained (docs/kernels.md).
bool compacts(const AccelInput& in) { return in.type == VK_ACCELERATION_STRUCTURE_TYPE_BOTTOM_LEVEL_KHR; }

VkAccelerationStructureBuildGeometryInfoKHR build_info(const AccelInput& in,
                                                       const VkAccelerationStructureGeometryKHR* g) {
  VkAccelerationStructureBuildGeometryInfoKHR info{VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_BUILD_GEOMETRY_INFO_KHR};
  info.type = in.type;
  info.flags = VK_BUILD_ACCELERATION_STRUCTURE_PREFER_FAST_TRACE_BIT_KHR;
  if (compacts(in)) info.flags |= VK_BUILD_ACCELERATION_STRUCTURE_ALLOW_COMPACTION_BIT_KHR;
  info.mode = VK_BUILD_ACCELERATION_STRUCTURE_MODE_BUILD_KHR;
  info.geometryCount = 1;
  info.pGeometries = g;
  return info;
}

} // namespace

// One call of build_accels: the batch being gathered and the block the finished
// structures are placed in.
class AccelBatch {
 public:
  AccelBatch(Context& ctx, const char* backend, const AccelBatchLimits& limits)
      : ctx_(ctx), backend_(backend), max_alloc_(ctx.max_allocation_bytes()),
        batch_bytes_(std::min(limits.batch_bytes, max_alloc_)), batch_builds_(std::max<std::size_t>(limits.batch_builds, 1)),
        block_bytes_(std::min(limits.block_bytes, max_alloc_)) {}

  void add(std::size_t id, AccelInput in) {
    Pending p;
    p.id = id;
    p.in = std::move(in);
    VkAccelerationStructureGeometryKHR g = geometry_of(p.in, 0);
    VkAccelerationStructureBuildGeometryInfoKHR info = build_info(p.in, &g);
    ctx_.accel().build_sizes(ctx_.device(), VK_ACCELERATION_STRUCTURE_BUILD_TYPE_DEVICE_KHR, &info, &p.in.count,
                             &p.sizes);
    check(id, "build storage", p.sizes.accelerationStructureSize + kStorageAlign);
    check(id, "build scratch", p.sizes.buildScratchSize + scratch_align());
    check(id, "input", p.in.data.size() + kInputAlign);
    // Only structures to compact take room in the batch's temporary storage.
    const VkDeviceSize storage = compacts(p.in) ? align_up(p.sizes.accelerationStructureSize, kStorageAlign) : 0;
    const VkDeviceSize scratch = align_up(p.sizes.buildScratchSize, scratch_align());
    const VkDeviceSize data = align_up(p.in.data.size(), kInputAlign);
    if (!pending_.empty() && (pending_.size() >= batch_builds_ || storage_ + storage > batch_bytes_ ||
                              scratch_ + scratch + scratch_align() > batch_bytes_ || input_ + data > batch_bytes_))
      flush();
    p.storage_offset = storage_;
    p.scratch_offset = scratch_;
    p.input_offset = input_;
    storage_ += storage;
    scratch_ += scratch;
    input_ += data;
    pending_.push_back(std::move(p));
  }

  // Builds, queries, compacts and frees the gathered batch.
  void flush() {
    if (pending_.empty()) return;
    const std::size_t n = pending_.size();
    Buffer input(ctx_, input_,
                 VK_BUFFER_USAGE_ACCELERATION_STRUCTURE_BUILD_INPUT_READ_ONLY_BIT_KHR |
                     VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT);
    Buffer storage = storage_ > 0 ? Buffer(ctx_, storage_, kStorageUsage) : Buffer(); // top levels alone: none
    // The base address rounded up to the scratch alignment, each region's offset a multiple of it.
    Buffer scratch(ctx_, scratch_ + scratch_align(),
                   VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT,
                   BufferRole::AccelScratch);
    const VkDeviceAddress scratch_base = align_up(scratch.address(), scratch_align());
    const VkDeviceAddress input_base = input.address();
    std::vector<AccelStructure> out(n);
    std::vector<VkAccelerationStructureKHR> built(n, VK_NULL_HANDLE);
    std::vector<std::size_t> compacted; // indices of the structures built to be compacted
    // The structures built to be compacted and their size queries: the structures go
    // first, then the queries, then the buffers above, whether the batch ends or throws.
    DeviceOwned<VkQueryPool> pool(ctx_.device(), vkDestroyQueryPool);
    std::vector<DeviceOwned<VkAccelerationStructureKHR>> uncompacted(n);
    // One upload for the batch: where buffers are device-local each upload is a copy
    // through staging, so per-structure uploads would cost a submission each.
    std::vector<std::byte> inputs(input_);
    for (const Pending& p : pending_)
      std::copy(p.in.data.begin(), p.in.data.end(), inputs.begin() + std::ptrdiff_t(p.input_offset));
    input.upload(inputs.data(), inputs.size());
    std::vector<VkAccelerationStructureGeometryKHR> geoms(n);
    std::vector<VkAccelerationStructureBuildGeometryInfoKHR> infos(n);
    std::vector<VkAccelerationStructureBuildRangeInfoKHR> ranges(n);
    std::vector<const VkAccelerationStructureBuildRangeInfoKHR*> range_ptrs(n);
    for (std::size_t i = 0; i < n; ++i) {
      Pending& p = pending_[i];
      if (compacts(p.in)) {
        VkAccelerationStructureCreateInfoKHR ci{VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_CREATE_INFO_KHR};
        ci.buffer = storage.handle();
        ci.offset = p.storage_offset;
        ci.size = p.sizes.accelerationStructureSize;
        ci.type = p.in.type;
        compacted.push_back(i);
        uncompacted[i] = {ctx_.device(), ctx_.accel().destroy};
        MASQ_VK_CHECK(ctx_.accel().create(ctx_.device(), &ci, nullptr, uncompacted[i].put()));
        built[i] = uncompacted[i].get();
      } else {
        place(out[i], p.id, p.sizes.accelerationStructureSize, p.in.type); // its final place
        built[i] = out[i].handle();
      }
      geoms[i] = geometry_of(p.in, input_base + p.input_offset);
      infos[i] = build_info(p.in, &geoms[i]);
      infos[i].dstAccelerationStructure = built[i];
      infos[i].scratchData.deviceAddress = scratch_base + p.scratch_offset;
      ranges[i] = {p.in.count, 0, 0, 0};
      range_ptrs[i] = &ranges[i];
    }
    std::vector<VkAccelerationStructureKHR> to_query;
    for (std::size_t i : compacted) to_query.push_back(built[i]);
    const auto queries = static_cast<std::uint32_t>(to_query.size());
    if (queries > 0) {
      VkQueryPoolCreateInfo qci{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
      qci.queryType = VK_QUERY_TYPE_ACCELERATION_STRUCTURE_COMPACTED_SIZE_KHR;
      qci.queryCount = queries;
      MASQ_VK_CHECK(vkCreateQueryPool(ctx_.device(), &qci, nullptr, pool.put()));
    }

    VkCommandBuffer cmd = ctx_.begin_commands(); // nothing below throws until the submit
    if (queries > 0) vkCmdResetQueryPool(cmd, pool.get(), 0, queries);
    ctx_.accel().cmd_build(cmd, static_cast<std::uint32_t>(n), infos.data(), range_ptrs.data());
    barrier_after_accel_build(ctx_, cmd);
    if (queries > 0)
      ctx_.accel().cmd_write_properties(cmd, queries, to_query.data(),
                                        VK_QUERY_TYPE_ACCELERATION_STRUCTURE_COMPACTED_SIZE_KHR, pool.get(), 0);
    ctx_.submit_and_wait(cmd);

    if (queries > 0) {
      std::vector<std::uint64_t> sizes(queries, 0);
      MASQ_VK_CHECK(vkGetQueryPoolResults(ctx_.device(), pool.get(), 0, queries, queries * sizeof(std::uint64_t),
                                          sizes.data(), sizeof(std::uint64_t),
                                          VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT));
      for (std::size_t k = 0; k < compacted.size(); ++k) {
        const Pending& p = pending_[compacted[k]];
        place(out[compacted[k]], p.id, std::max<std::uint64_t>(sizes[k], 1), p.in.type);
      }
      cmd = ctx_.begin_commands();
      for (std::size_t i : compacted) {
        VkCopyAccelerationStructureInfoKHR copy{VK_STRUCTURE_TYPE_COPY_ACCELERATION_STRUCTURE_INFO_KHR};
        copy.src = built[i];
        copy.dst = out[i].handle();
        copy.mode = VK_COPY_ACCELERATION_STRUCTURE_MODE_COMPACT_KHR;
        ctx_.accel().cmd_copy(cmd, &copy);
      }
      barrier_after_accel_build(ctx_, cmd);
      ctx_.submit_and_wait(cmd);
    }
    for (std::size_t i = 0; i < n; ++i) {
      VkAccelerationStructureDeviceAddressInfoKHR ai{VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_DEVICE_ADDRESS_INFO_KHR};
      ai.accelerationStructure = out[i].handle();
      out[i].address_ = ctx_.accel().device_address(ctx_.device(), &ai);
      done_.push_back(std::move(out[i]));
    }
    pending_.clear();
    storage_ = scratch_ = input_ = 0;
  }

  std::vector<AccelStructure> take() { return std::move(done_); }

 private:
  struct Pending {
    std::size_t id = 0;
    AccelInput in;
    VkAccelerationStructureBuildSizesInfoKHR sizes{VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_BUILD_SIZES_INFO_KHR};
    VkDeviceSize storage_offset = 0, scratch_offset = 0, input_offset = 0;
  };

  VkDeviceSize scratch_align() const {
    return std::max<VkDeviceSize>(ctx_.accel_props().minAccelerationStructureScratchOffsetAlignment, 1);
  }

  void check(std::size_t id, const char* what, VkDeviceSize bytes) const {
    if (bytes > max_alloc_)
      throw Error(fmt::format("{}: acceleration structure {} needs {} bytes of {} in one buffer; the device allows {} "
                              "({})",
                              backend_, id, bytes, what, max_alloc_, ctx_.max_allocation_name()));
  }

  // A structure of `bytes` (compacted, or a top level's build size) at the next
  // 256-aligned offset of the current block, or of a new one (its own when larger
  // than a block).
  void place(AccelStructure& as, std::size_t id, std::uint64_t bytes, VkAccelerationStructureTypeKHR type) {
    if (!block_ || block_used_ + bytes > block_->size()) {
      check(id, "compacted storage", bytes);
      block_ = std::make_shared<Buffer>(ctx_, std::max<VkDeviceSize>(block_bytes_, bytes), kStorageUsage);
      block_used_ = 0;
    }
    VkAccelerationStructureCreateInfoKHR ci{VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_CREATE_INFO_KHR};
    ci.buffer = block_->handle();
    ci.offset = block_used_;
    ci.size = bytes;
    ci.type = type;
    as.block_ = block_;
    as.bytes_ = static_cast<std::size_t>(bytes);
    as.handle_ = {ctx_.device(), ctx_.accel().destroy};
    MASQ_VK_CHECK(ctx_.accel().create(ctx_.device(), &ci, nullptr, as.handle_.put()));
    block_used_ = align_up(block_used_ + bytes, kStorageAlign);
  }

  Context& ctx_;
  const char* backend_;
  VkDeviceSize max_alloc_, batch_bytes_;
  std::size_t batch_builds_;
  VkDeviceSize block_bytes_;
  std::vector<Pending> pending_;
  VkDeviceSize storage_ = 0, scratch_ = 0, input_ = 0; // the batch's buffers, so far
  std::shared_ptr<Buffer> block_;
  VkDeviceSize block_used_ = 0;
  std::vector<AccelStructure> done_;
};

std::vector<AccelStructure> build_accels(Context& ctx, const char* backend, std::size_t count,
                                         const std::function<AccelInput(std::size_t)>& input,
                                         const AccelBatchLimits& limits) {
  AccelBatch batch(ctx, backend, limits);
  for (std::size_t i = 0; i < count; ++i) batch.add(i, input(i));
  batch.flush();
  return batch.take();
}

} // namespace masq::vk
