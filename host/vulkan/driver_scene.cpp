#include "host/vulkan/driver_scene.h"
#include "bvh/bounds/obb.h"
#include "bvh/bounds/prim_bounds.h"
#include "bvh/nodes/compact_instance.h"
#include "scenes/prim_table.h"
#include "bvh/twolevel/cluster_blas.h"
#include "host/limit_knob.h"
#include "host/vulkan/vulkan_backends.h"
#include "kernels/kernel_data.h"
#include <fmt/format.h>
#include <algorithm>
#include <cmath>

namespace masq::vk {
namespace {

// The driver tests the unit box in its own fp32 object space; the masquerade transform
// scales a thin capsule's radius up to 1, so the object-space origin carries an error
// of about gamma_4 |A| |o| (~6e-4 for r = 0.002 seen from 5 units). The box is padded
// by this relative margin so that the driver's cull never rejects a ray the world-space
// intersector would hit; it enlarges the box by 0.1 %, which changes call counts by
// about as much.
constexpr float kUnitBoxMargin = 1e-3f;
// Capsule AABBs (reference method) are padded by this fraction of their largest
// coordinate magnitude or extent, to absorb the driver's own box-test rounding.
constexpr float kAabbMargin = 1e-5f;

// Robust mode: the driver's own fp32 ray transform into a masquerade instance errs by
// up to gamma_4 (|A_k| . |o| + |b_k|) on unit axis k (docs/robustness.md), which far
// from the world origin (|b| ~ |A| |c|) exceeds any fixed margin. The unit box cannot be
// padded per ray inside the driver, so each instance's OBB is widened per axis by that
// bound for every ray origin within `reach` of the world origin (every coordinate at
// most reach). The reach starts at twice the largest OBB centre coordinate plus one;
// a batch whose rays start farther out rebuilds the TLAS with a larger reach first.
Mat3x4f widened_unit_to_world(const kernel::Instance& inst, const Mat3x4f& unit_to_world, double reach) {
  constexpr double kGamma4 = 4.0 * 5.9604645e-8 / (1.0 - 4.0 * 5.9604645e-8);
  Mat3x4f m = unit_to_world;
  for (int k = 0; k < 3; ++k) {
    const float* row = inst.world_to_object + 4 * k;
    double a = std::fabs(row[0]) + std::fabs(row[1]) + std::fabs(row[2]);
    double pad = 2.0 * kGamma4 * (a * reach + std::fabs(row[3]));
    // Column k of the unit -> world map scales unit axis k.
    for (int r = 0; r < 3; ++r) m[std::size_t(4 * r + k)] = float(double(m[std::size_t(4 * r + k)]) * (1.0 + pad));
  }
  return m;
}

double origin_reach(const PackedScene& s) {
  double far = 0.0;
  for (const Mat3x4f& m : s.instance_object_to_world)
    far = std::max({far, std::fabs(double(m[3])), std::fabs(double(m[7])), std::fabs(double(m[11]))});
  return 2.0 * far + 1.0;
}

// One TLAS part as the driver kernels read it (kernels/rayquery.comp, kernels/rtpipeline.rgen).
struct TlasPartRecord {
  std::uint64_t address;
  std::int32_t first; // its first entry (instance record)
  std::int32_t pad;
};
static_assert(sizeof(TlasPartRecord) == 16);

VkTransformMatrixKHR to_vk(const Mat3x4f& m) {
  VkTransformMatrixKHR t{};
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c) t.matrix[r][c] = m[static_cast<std::size_t>(r * 4 + c)];
  return t;
}

// The driver's AABB of a procedural primitive: the exact box of its ball hull (from
// the fp32 data the intersector reads), padded and rounded outward.
VkAabbPositionsKHR procedural_box(const PackedScene& s, int geom, int prim) {
  Aabb b = hull_box(ball_hull(s, geom, prim));
  double scale = 0.0;
  for (int k = 0; k < 3; ++k) scale = std::max({scale, std::fabs(b.lo[k]), std::fabs(b.hi[k]), b.hi[k] - b.lo[k]});
  double pad = scale * kAabbMargin;
  return {round_down(b.lo.x - pad), round_down(b.lo.y - pad), round_down(b.lo.z - pad),
          round_up(b.hi.x + pad),   round_up(b.hi.y + pad),   round_up(b.hi.z + pad)};
}

} // namespace

KernelFeatures DriverScene::set(const PackedScene& scene) {
  kept_.reset();
  tlas_.clear();
  parts_buffer_ = Buffer();
  blas_.clear();
  unit_box_ = AccelStructure();
  scene_ = SceneBuffers{};
  check_inputs(scene);
  plan_ = plan_ray_query(scene, max_primitives(), backend_); // BLAS ids and TLAS entries
  // The driver's structures replace masq's own BVH (nodes, refs, compact entries), and
  // the instance records in submission order the scene's (upload_instance_records).
  SceneArrayData arrays = scene_array_data(scene);
  for (SceneArray a : {SceneArray::nodes, SceneArray::refs, SceneArray::masq_instances, SceneArray::masq_owners,
                       SceneArray::instances})
    arrays[a] = {};
  add_scene_arrays(scene_, ctx_, backend_, arrays, KernelFamily::TwoLevel);
  upload_instance_records(scene);
  scene_.add(ctx_, backend_, MASQ_BINDING_PRIM_MAP, "primitive id map", primitive_id_map(scene, plan_));
  scene_.finish(ctx_, backend_);
  reach_ = origin_reach(scene);
  build_structures(scene);
  if (scene.features.mode == Mode::Robust && scene.method != Method::Ref) kept_ = scene; // for TLAS rebuilds
  scene_.bind(layout_);
  KernelFeatures f = scene.features;
  f.tlas_stack = f.blas_stack = StackNeed{};
  return f;
}

std::size_t DriverScene::device_bytes() const {
  std::size_t b = scene_.bytes + parts_buffer_.size() + unit_box_.bytes();
  for (const auto& as : tlas_) b += as.bytes();
  for (const auto& as : blas_) b += as.bytes();
  return b;
}

void DriverScene::check_inputs(const PackedScene& s) const {
  if (s.frame_object_to_world.size() != s.frames.size())
    throw Error(fmt::format("{}: {} frames but {} frame_object_to_world transforms", backend_, s.frames.size(),
                            s.frame_object_to_world.size()));
  if (s.tlas_leaf_order.size() != s.tlas_entry_count())
    throw Error(fmt::format("{}: tlas_leaf_order has {} entries for {} instances", backend_, s.tlas_leaf_order.size(),
                            s.tlas_entry_count()));
  for (std::int32_t i : s.tlas_leaf_order)
    if (i < 0 || static_cast<std::size_t>(i) >= s.tlas_entry_count())
      throw Error(fmt::format("{}: tlas_leaf_order names instance {} of {}", backend_, i, s.tlas_entry_count()));
}

std::uint64_t DriverScene::max_instances() const {
  return lowered_limit(backend_, ctx_.accel_props().maxInstanceCount, Knob::RqMaxInstances);
}
std::uint64_t DriverScene::max_primitives() const {
  return lowered_limit(backend_, ctx_.accel_props().maxPrimitiveCount, Knob::RqMaxPrimitives);
}

// One Instance record per TLAS entry, in submission order (the shader reads record
// parts[p].first + custom index); compact masquerade entries are expanded, since the
// driver's instance, not the record, carries their map.
void DriverScene::upload_instance_records(const PackedScene& s) {
  scene_.add(ctx_, backend_, info(SceneArray::instances).binding, "instance records (one per TLAS entry)",
             plan_.entries.size() * sizeof(kernel::Instance), [&](Buffer& b) {
               std::vector<kernel::Instance> chunk;
               constexpr std::size_t kChunk = 1 << 16;
               for (std::size_t first = 0; first < plan_.entries.size(); first += kChunk) {
                 std::size_t n = std::min(kChunk, plan_.entries.size() - first);
                 chunk.resize(n);
                 for (std::size_t k = 0; k < n; ++k)
                   chunk[k] = tlas_entry_instance(s, static_cast<std::size_t>(plan_.entries[first + k].inst));
                 b.upload(chunk.data(), n * sizeof(kernel::Instance), first * sizeof(kernel::Instance));
               }
             });
}

// The driver BLAS of a cluster: each member's exact local box under every scene
// instance's stored maps (bvh/twolevel/cluster_blas.h), padded per local axis by twice the
// driver's fp32 transform error for any origin within reach_ and any point it can
// hit (|t d| <= 3 reach_): 2 (gamma_4 (|S_k|_1 reach + |s_k|) + gamma_3 |S_k|_1 3 reach).
AccelInput DriverScene::cluster_input(const PackedScene& s, int root) const {
  constexpr double kGamma4 = 4.0 * 5.9604645e-8 / (1.0 - 4.0 * 5.9604645e-8);
  constexpr double kGamma3 = 3.0 * 5.9604645e-8 / (1.0 - 3.0 * 5.9604645e-8);
  std::vector<std::int32_t> members = cluster_members(s, root);
  if (members.size() > max_primitives())
    throw Error(fmt::format("{}: a cluster of {} members exceeds maxPrimitiveCount {}", backend_, members.size(),
                            max_primitives()));
  std::vector<Aabb> local(members.size());
  glm::dvec3 pad(0.0);
  for (const kernel::Instance& inst : s.instances) {
    if (inst.prim != MASQ_INST_CLUSTER || inst.blas_root != root) continue;
    Mat3x4f w2l, frame;
    std::copy(std::begin(inst.world_to_object), std::end(inst.world_to_object), w2l.begin());
    const float* f = s.frames.at(static_cast<std::size_t>(inst.scene_inst)).world_to_object;
    std::copy(f, f + 12, frame.begin());
    Affine3 realised = realised_object_to_local(w2l, frame);
    const glm::dvec3 row_len = row_lengths(realised);
    for (std::size_t m = 0; m < members.size(); ++m)
      local[m].grow(hull_world_box(ball_hull(s, inst.geom, members[m]), realised, row_len));
    for (int k = 0; k < 3; ++k) {
      const float* row = inst.world_to_object + 4 * k;
      double a = std::fabs(row[0]) + std::fabs(row[1]) + std::fabs(row[2]);
      pad[k] = std::max(pad[k], 2.0 * (kGamma4 * (a * reach_ + std::fabs(row[3])) + kGamma3 * a * 3.0 * reach_));
    }
  }
  std::vector<VkAabbPositionsKHR> boxes;
  boxes.reserve(members.size());
  for (const Aabb& b : local)
    boxes.push_back({round_down(b.lo.x - pad.x), round_down(b.lo.y - pad.y), round_down(b.lo.z - pad.z),
                     round_up(b.hi.x + pad.x), round_up(b.hi.y + pad.y), round_up(b.hi.z + pad.z)});
  return aabb_input(boxes);
}

// The BLAS of `spec`: a run of its geometry's leaf order.
AccelInput DriverScene::geometry_input(const PackedScene& s, const RayQueryPlan::Blas& spec) const {
  const kernel::Geometry& geo = s.geoms.at(static_cast<std::size_t>(spec.geom));
  auto all = geometry_leaf_order(s, static_cast<std::size_t>(spec.geom));
  std::span<const std::int32_t> order(all.data() + spec.first, spec.count);
  if (scene_prim_row_of_kernel_type(geo.type).mesh) {
    std::vector<float> v;
    v.reserve(order.size() * 9);
    for (std::int32_t p : order) {
      const kernel::Triangle& t = s.triangles.at(static_cast<std::size_t>(geo.first + p));
      v.insert(v.end(), {t.v0[0], t.v0[1], t.v0[2], t.v1[0], t.v1[1], t.v1[2], t.v2[0], t.v2[1], t.v2[2]});
    }
    return triangle_input(v);
  }
  std::vector<VkAabbPositionsKHR> boxes;
  boxes.reserve(order.size());
  for (std::int32_t p : order) boxes.push_back(procedural_box(s, spec.geom, p));
  return aabb_input(boxes);
}

// Every BLAS of the plan and the unit box when an entry needs it, in batches
// (build_accels), then the TLAS parts over them.
void DriverScene::build_structures(const PackedScene& s) {
  tlas_.clear();
  const std::size_t n = plan_.blas.size();
  std::vector<AccelStructure> built =
      build_accels(ctx_, backend_, n + (plan_.unit_box ? 1 : 0), [&](std::size_t b) {
        if (b == n) {
          const float m = 1.0f + kUnitBoxMargin;
          const VkAabbPositionsKHR box{-m, -m, -m, m, m, m};
          return aabb_input(std::span<const VkAabbPositionsKHR>(&box, 1));
        }
        const RayQueryPlan::Blas& spec = plan_.blas[b];
        return spec.geom >= 0 ? geometry_input(s, spec) : cluster_input(s, spec.root);
      });
  unit_box_ = plan_.unit_box ? std::move(built.back()) : AccelStructure();
  built.resize(n);
  blas_ = std::move(built);
  build_tlas(s);
}

// Robust masquerade: make sure the instance OBBs are widened for every origin of
// this batch (see widened_unit_to_world); rebuilds the TLAS when one starts farther
// out than the current reach (doubling, so a growing sequence rebuilds rarely).
void DriverScene::widen_for(std::span<const kernel::Ray> rays) {
  if (!kept_) return;
  double far = 0.0;
  for (const kernel::Ray& r : rays)
    for (float c : r.org)
      if (std::isfinite(c)) far = std::max(far, double(std::fabs(c)));
  if (far <= reach_) return;
  reach_ = std::max(2.0 * reach_, far);
  build_structures(*kept_); // the cluster BLAS's padding depends on the reach too
}

// The TLAS parts: runs of at most maxInstanceCount entries of plan_.entries, each built in
// submission order; then the parts table (MASQ_BINDING_TLAS_PARTS).
void DriverScene::build_tlas(const PackedScene& s) {
  tlas_.clear();
  const std::uint64_t max_inst = std::min<std::uint64_t>(max_instances(), (1u << 24) - 1); // custom index
  if (plan_.entries.size() > std::size_t(INT32_MAX))
    throw Error(fmt::format("{}: more than 2^31-1 TLAS entries", backend_));
  part_size_ = static_cast<std::size_t>(max_inst);
  const std::size_t parts = (plan_.entries.size() + max_inst - 1) / max_inst;
  tlas_ = build_accels(ctx_, backend_, parts, [&](std::size_t p) {
    const std::size_t first = p * max_inst;
    const std::size_t n = std::min<std::size_t>(max_inst, plan_.entries.size() - first);
    std::vector<VkAccelerationStructureInstanceKHR> part;
    part.reserve(n);
    for (std::size_t k = 0; k < n; ++k) part.push_back(tlas_entry(s, plan_.entries[first + k], std::uint32_t(k)));
    return instance_input(part);
  });
  std::vector<TlasPartRecord> records;
  for (std::size_t p = 0; p < parts; ++p)
    records.push_back({tlas_[p].address(), static_cast<std::int32_t>(p * max_inst), 0});
  parts_buffer_ = Buffer(ctx_, std::max<std::size_t>(records.size(), 1) * sizeof(TlasPartRecord),
                         VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
  parts_buffer_.upload(records.data(), records.size() * sizeof(TlasPartRecord));
  layout_.bind_buffer(MASQ_BINDING_TLAS_PARTS, parts_buffer_);
}

VkAccelerationStructureInstanceKHR DriverScene::tlas_entry(const PackedScene& s, const RayQueryPlan::Entry& en,
                                                           std::uint32_t rank) {
  const bool robust = s.features.mode == Mode::Robust;
  const std::size_t i = static_cast<std::size_t>(en.inst);
  const kernel::Instance inst = tlas_entry_instance(s, i); // a compact entry with its decoded map
  VkAccelerationStructureInstanceKHR e{};
  e.instanceCustomIndex = rank;
  e.mask = 0xFF;
  e.instanceShaderBindingTableRecordOffset =
      sbt_record_offset(plan_, en, s.geoms.at(static_cast<std::size_t>(inst.geom)).type);
  e.flags = VK_GEOMETRY_INSTANCE_TRIANGLE_FACING_CULL_DISABLE_BIT_KHR;
  if (inst.prim == MASQ_INST_CLUSTER) {
    if (i >= s.instance_object_to_world.size())
      throw Error(fmt::format("{}: instance {} has no instance_object_to_world transform", backend_, i));
    e.transform = to_vk(s.instance_object_to_world[i]);
    e.accelerationStructureReference = blas_.at(static_cast<std::size_t>(en.blas)).address();
  } else if (inst.blas_root >= 0) {
    e.transform = to_vk(s.frame_object_to_world.at(static_cast<std::size_t>(inst.scene_inst)));
    e.accelerationStructureReference = blas_.at(static_cast<std::size_t>(en.blas)).address();
  } else {
    if (i >= s.instance_object_to_world.size())
      throw Error(fmt::format("{}: instance {} has no instance_object_to_world transform", backend_, i));
    const Mat3x4f& u2w = s.instance_object_to_world[i];
    e.transform = to_vk(robust ? widened_unit_to_world(inst, u2w, reach_) : u2w);
    e.accelerationStructureReference = unit_box_.address();
  }
  return e;
}

} // namespace masq::vk
