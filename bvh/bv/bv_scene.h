// A scene built as ONE binary bounding-volume hierarchy over the world-space primitives
// of every instance (no TLAS), with AABB, ball, OBB or slab-cut-ball nodes: the
// hierarchies Kallberg & Larsson compare ("Ray Tracing using Hierarchies of Slab Cut
// Balls"). Traced by the bv kernels (kernels/bv_traverse.h) through host/bv_tracer.h.
#pragma once
#include "bvh/binary/binned_sah.h"
#include "bvh/packed_scene.h"
#include "bvh/bounds/prim_bounds.h"
#include "masq/names.h"
#include "scenes/scene.h"
#include <memory>
#include <string>
#include <vector>

namespace masq {

enum class BvType { Aabb, Sphere, Obb, Scb };
inline constexpr NameRow<BvType> bv_type_rows[] = {
    {BvType::Aabb, "aabb", "axis-aligned boxes"},
    {BvType::Sphere, "sphere", "balls"},
    {BvType::Obb, "obb", "oriented boxes"},
    {BvType::Scb, "scb", "slab-cut balls"},
};
inline constexpr NameTable bv_type_table{"bounding-volume type", bv_type_rows};
inline const char* bv_type_name(BvType t) { return bv_type_table.name(t); }
int bv_type_kernel_id(BvType t); // MASQ_BV_*

// The sweep is bvh/bv/obb_sweep_bvh.h, the binned SAH bvh/binary/binned_sah.h.
enum class BvBuilder { ObbSweep, BinnedSah };
inline constexpr NameRow<BvBuilder> bv_builder_rows[] = {
    {BvBuilder::ObbSweep, "obb-sweep", "the SCB paper's top-down SAH sweep with OBB areas"},
    {BvBuilder::BinnedSah, "binned-sah", "the project's binned SAH over world AABBs"},
};
inline constexpr NameTable bv_builder_table{"bounding-volume builder", bv_builder_rows};
inline const char* bv_builder_name(BvBuilder b) { return bv_builder_table.name(b); }

struct BvOptions {
  BvType type = BvType::Scb;
  BvBuilder builder = BvBuilder::ObbSweep;
  double scb_p = 0.2; // slab choice: reduced area (1 - p * (1 - |n . n_parent|)) * area
  SahOptions sah;
};

struct BvStats {
  std::size_t nodes = 0, leaves = 0;
  int depth = 0;
  double build_seconds = 0;
};

struct BvScene {
  BvType type = BvType::Scb;
  // Frames, geometries and primitive arrays as the two-level kernels get them (from
  // build_accel's ref packing). Its wide nodes and refs are dropped; its instances stay
  // as the list of (frame, geometry) placements (world_prims reads them).
  PackedScene prims;
  // Exactly one of these is filled, by `type`. The names are the kernels' (the BV rows
  // of kernels/scene_array_table.h).
  std::vector<kernel::BvNodeAabb> bv_aabb;
  std::vector<kernel::BvNodeSphere> bv_sphere;
  std::vector<kernel::BvNodeObb> bv_obb;
  std::vector<kernel::BvNodeScb> bv_scb;
  std::vector<kernel::BvPrimRef> bv_prims; // leaf entries, leaf order
  BvStats stats;
  std::size_t node_count() const;
  std::size_t node_bytes() const;
};

// Every primitive of every instance as a world-space hull (triangles: their three
// vertices as zero-radius balls), from the fp32 arrays the kernels intersect, placed by
// the inverse of each frame's STORED fp32 world-to-object map. A ball under a
// non-similarity map becomes an ellipsoid; it is covered by the ball of radius
// r * sigma_max (bounded above by Gershgorin on L^T L).
struct WorldPrims {
  std::vector<BallHull> hulls;
  std::vector<kernel::BvPrimRef> refs; // same index
};
WorldPrims world_prims(const PackedScene& prims);

// The part of a build every BV type shares: packed primitives, world hulls and the
// topology of opt.builder (the volume type does not change the topology).
struct BvTopology;
struct BvTopologyDeleter {
  void operator()(BvTopology* t) const;
};
using BvTopologyPtr = std::unique_ptr<BvTopology, BvTopologyDeleter>;

// Throws masq::Error for invalid scenes (validate_scene), empty scenes or a tree deeper
// than the kernels' traversal stack.
BvTopologyPtr build_bv_topology(const Scene& scene, const BvOptions& opt = {});
// Fits opt.type's volumes (and opt.scb_p) onto a topology; build_seconds = this fit.
BvScene fit_bv_scene(const BvTopology& topo, const BvOptions& opt);
double bv_topology_seconds(const BvTopology& topo);

BvScene build_bv_scene(const Scene& scene, const BvOptions& opt = {});

} // namespace masq
