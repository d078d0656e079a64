// A PackedScene as the driver's own acceleration structures (VK_KHR_acceleration_
// structure), shared by the two backends whose traversal the driver does: rayquery
// (kernels/rayquery.comp) and rtpipeline (kernels/rtpipeline.*).
//   Method::Ref:  one BLAS per geometry (triangles opaque; capsules as their AABBs), one
//                 TLAS instance per scene instance.
//   Method::Masq: one BLAS holding the unit box (padded, see kUnitBoxMargin), one TLAS
//                 instance per primitive mapping it onto the primitive's OBB; triangle
//                 geometries keep a triangle BLAS per geometry.
//   Method::Cluster (and auto's clusters): one AABB BLAS per cluster over its members'
//                 local boxes, one TLAS instance per (scene instance, cluster) with the
//                 cluster's local-to-world transform. auto's ordinary BLAS may hold a
//                 subset of a geometry.
// Every BLAS has an id b (geometry parts first, then clusters); a TLAS entry's SBT
// record offset is its BLAS id, or for a masquerade entry the number of BLAS plus its
// primitive type (rayquery_plan.h, sbt_record_offset), and prim_map[prim_map[b] + driver
// primitive index] is the primitive. Beyond the driver's limits (maxPrimitiveCount per
// BLAS, maxInstanceCount per TLAS; 2^24-1 on lavapipe; lowered by MASQ_RQ_MAX_PRIMITIVES /
// MASQ_RQ_MAX_INSTANCES, host/limit_knob.h) a geometry's leaf order is cut into several
// BLAS (each placed by its own TLAS entry) and the TLAS entries into several TLAS
// ("parts", traced in turn). The instance records are uploaded one per TLAS entry in
// submission order, so the 24-bit custom index is the entry's rank within its part and
// any instance count maps back exactly.
// Every BLAS, then the TLAS parts, is built in batches into shared storage blocks, the
// BLAS compacted (vk::build_accels, host/vulkan/accel_batch.cpp); device_bytes counts
// the BLAS at their compacted sizes.
// lavapipe builds its BVH in submission order without sorting, so primitives and
// instances are submitted in the order of masq's own BVH leaves (PackedScene's
// geometry_leaf_order and tlas_leaf_order), and each part is a contiguous run of it.
#pragma once
#include "bvh/packed_scene.h"
#include "host/vulkan/acceleration_structures.h"
#include "host/vulkan/rayquery_plan.h"
#include "host/vulkan/trace_dispatch.h"
#include <optional>
#include <span>
#include <vector>

namespace masq::vk {

class DriverScene {
 public:
  // `backend` names the caller in errors; the scene arrays, the instance records, the
  // primitive id map and the TLAS parts table (MASQ_BINDING_TLAS_PARTS) are bound into
  // `layout` by set() and again after every rebuild.
  DriverScene(Context& ctx, KernelLayout& layout, const char* backend)
      : ctx_(ctx), layout_(layout), backend_(backend) {}

  // Uploads the arrays the driver kernels read and builds every structure; replaces any
  // previous scene. Returns the scene's kernel features as the driver kernels take them
  // (no kernel stacks: the driver traverses). Throws masq::Error naming the backend for
  // malformed scenes and limits no split can meet.
  KernelFeatures set(const PackedScene& scene);
  // Robust masquerade: make sure the instance OBBs are widened for every origin of this
  // batch; rebuilds the structures when one starts farther out than the current reach.
  void widen_for(std::span<const kernel::Ray> rays);

  bool addressed() const { return scene_.addressed(); }
  const RayQueryPlan& plan() const { return plan_; }
  std::size_t part_count() const { return tlas_.size(); }
  std::size_t part_first(std::size_t p) const { return p * part_size_; } // its first TLAS entry
  // The driver's structures at their sizes on the device, the arrays and the tables.
  std::size_t device_bytes() const;

 private:
  void check_inputs(const PackedScene& s) const;
  std::uint64_t max_instances() const;
  std::uint64_t max_primitives() const;
  void upload_instance_records(const PackedScene& s);
  AccelInput cluster_input(const PackedScene& s, int root) const;
  AccelInput geometry_input(const PackedScene& s, const RayQueryPlan::Blas& spec) const;
  void build_structures(const PackedScene& s);
  void build_tlas(const PackedScene& s);
  VkAccelerationStructureInstanceKHR tlas_entry(const PackedScene& s, const RayQueryPlan::Entry& en,
                                                std::uint32_t rank);

  Context& ctx_;
  KernelLayout& layout_;
  const char* backend_;
  SceneBuffers scene_;
  RayQueryPlan plan_;
  std::vector<AccelStructure> blas_; // by BLAS id: geometry parts, then clusters
  AccelStructure unit_box_;
  std::vector<AccelStructure> tlas_; // the parts
  std::size_t part_size_ = 1;        // TLAS entries per part (the last may hold fewer)
  Buffer parts_buffer_;
  double reach_ = 1.0;              // robust masquerade: origins covered by the OBB widening
  std::optional<PackedScene> kept_; // robust masquerade scenes, for TLAS rebuilds
};

} // namespace masq::vk
