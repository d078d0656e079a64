// The bvh layer's table of primitive types: how each becomes the kernels' arrays (its
// MASQ_PRIM_* id, its array in PackedScene, its MASQ_HAVE_* feature) and what its
// intersector costs. Builders, bounds and cost models call through the row or read its
// columns instead of comparing types (docs/architecture.md, "The tables").
#pragma once
#include "bvh/packed_scene.h"
#include "scenes/prim_table.h"
#include <cstddef>

namespace masq {

struct BvhPrimRow {
  PrimType type;
  int kernel_type;               // MASQ_PRIM_* of kernels/layout.h (row i has id i)
  bool KernelFeatures::*feature; // the MASQ_HAVE_* switch a scene holding it turns on
  // The intersector's cost relative to a capsule's: the structure cost model and the
  // SAH price of builders that price intersections (bvh/twolevel/structure_cost.h).
  double isect_factor;
  // Appends geometry g's primitives (fp32) to its PackedScene array; returns the index of
  // the first.
  int (*pack)(const Geometry& g, PackedScene& ps);
  // The hull balls of element `index` of its PackedScene array (a triangle: its vertices).
  int (*packed_balls)(const PackedScene& ps, std::size_t index, PrimBalls& out);
  std::size_t (*packed_bytes)(const PackedScene& ps); // its PackedScene array's bytes
};

const BvhPrimRow& bvh_prim_row(PrimType t);
// The row of a MASQ_PRIM_* id (a kernel::Geometry's type); throws masq::Error for none.
const BvhPrimRow& bvh_prim_row(int kernel_type);
// The scenes layer's row of a MASQ_PRIM_* id.
const ScenePrimRow& scene_prim_row_of_kernel_type(int kernel_type);

} // namespace masq
