// How the driver-traversal backends (rayquery, rtpipeline; host/vulkan/driver_scene.h)
// lay a PackedScene out for the driver, within its limits: which bottom-level
// structures (BLAS) to build, the TLAS entries in submission order, and the primitive id
// map the shaders read. Host-only, so the splitting can be reasoned about apart from Vulkan.
//  - BLAS ids: each geometry that a TLAS instance references by BLAS (ref, auto) gets
//    runs of its BVH leaf order of at most max_primitives each; then each cluster BLAS.
//    A TLAS entry's 24-bit SBT record offset is its BLAS id, or for a masquerade entry
//    the number of BLAS plus its primitive type (sbt_record_offset): rtpipeline's hit
//    records are laid out so (one per BLAS, then one per primitive type), and rayquery
//    reads the offset only as a BLAS id.
//  - TLAS entries follow tlas_leaf_order; a scene instance of a split geometry gets one
//    entry per run (each places its own BLAS with the same transform).
//  - prim_map[b] (b < number of BLAS) is where BLAS b's primitive ids start in prim_map,
//    in the order they are submitted to the driver.
#pragma once
#include "bvh/packed_scene.h"
#include "kernels/layout.h"
#include <cstdint>
#include <map>
#include <vector>

namespace masq::vk {

struct RayQueryPlan {
  // A BLAS: the run [first, first + count) of geometry `geom`'s leaf order, or (geom < 0)
  // the cluster whose masq BLAS root is `root`.
  struct Blas {
    int geom;
    int root;
    std::size_t first, count;
    int type; // its primitives' MASQ_PRIM_* (rtpipeline's hit group)
  };
  struct Entry {
    std::int32_t inst; // TLAS entry id (tlas_entry_instance, bvh/nodes/compact_instance.h)
    std::int32_t blas; // BLAS id; -1 for masquerade (the unit box)
  };
  std::vector<Blas> blas;               // by BLAS id
  std::vector<Entry> entries;           // TLAS entries in submission order
  std::map<int, std::int32_t> clusters; // cluster's masq BLAS root -> BLAS id
  bool unit_box = false;                // some entry is a masquerade instance (the unit-box BLAS)
};

// Throws masq::Error "<backend>: ..." for more SBT records than 24-bit offsets reach or a
// malformed leaf order. tlas_leaf_order must name valid TLAS entries.
RayQueryPlan plan_ray_query(const PackedScene& s, std::uint64_t max_primitives, const char* backend = "rayquery");

// The hit records a plan's TLAS entries reach: one per BLAS, then one per primitive type.
inline std::size_t sbt_record_count(const RayQueryPlan& plan) { return plan.blas.size() + MASQ_PRIM_TYPE_COUNT; }
// A TLAS entry's SBT record offset (above); prim_type: its geometry's MASQ_PRIM_*.
inline std::uint32_t sbt_record_offset(const RayQueryPlan& plan, const RayQueryPlan::Entry& e, int prim_type) {
  return static_cast<std::uint32_t>(e.blas >= 0 ? std::size_t(e.blas) : plan.blas.size() + std::size_t(prim_type));
}

// Primitive ids of geometry g in submission order (identity when the builder gave none;
// auto may keep a subset in its ordinary BLAS).
std::vector<std::int32_t> geometry_leaf_order(const PackedScene& s, std::size_t g);

// Member ids of the cluster BLAS at node `root`, in depth-first leaf order (the order
// its boxes are submitted in).
std::vector<std::int32_t> cluster_members(const PackedScene& s, int root);

// The offsets, then each BLAS's ids (see above).
std::vector<std::int32_t> primitive_id_map(const PackedScene& s, const RayQueryPlan& plan);

} // namespace masq::vk
