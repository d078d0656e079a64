// Expected work per ray of a built two-level structure, by the surface-area heuristic
// over its real nodes: a ray that hits the scene's bounding box reaches a box with
// probability (world surface area of the box) / (area of the scene box). Unlike the
// per-primitive model of bvh/twolevel/method_plan.cpp, it sees what the built TLAS and BLAS look
// like (depth, overlap, leaf sizes), so method auto can compare whole candidate
// structures (docs/methods.md).
#pragma once
#include "bvh/twolevel/method_plan.h"
#include "bvh/packed_scene.h"

namespace masq {

struct StructureCost {
  double nodes = 0;      // expected wide-node visits per ray (TLAS + BLAS)
  double transforms = 0; // expected instance transforms (with their unit-box or BLAS-root test)
  double isects = 0;     // expected intersector calls, each weighted by its type's price factor
  double total = 0;      // node * nodes + transform * transforms + isect * isects
  // The part of total spent in triangle geometries' BLAS (the same in every method, as
  // triangles always stay in a BLAS): auto compares candidates on total - triangles.
  double triangles = 0;
};

// Relative price of one intersector call per primitive type (capsule = 1). Measured
// on the cpu backend with the bear fur (docs/methods.md): the robust phantom curve
// costs about six capsule calls; round cones a little more than capsules.
double isect_type_factor(int kernel_prim_type);

// SAH intersection cost of one primitive of this type relative to one binary-BVH
// traversal step, from the default prices: a binary inner node is half a w4 visit (its
// two box tests of the four), so capsule 2.5 / 0.5 = 5 and the robust curve 30. The
// sah-priced builder's leaves use it; with it the SAH splits hair down to one primitive
// per leaf nearly everywhere, as a driver's BVH does (docs/builders.md).
double blas_isect_price(int kernel_prim_type);

// Walks ps's TLAS from ps.tlas_root (or its single BLAS when ps.features.single_blas),
// reading the w4 node array. A scene with no TLAS costs 0.
StructureCost structure_cost(const PackedScene& ps, const CostPrices& prices);

} // namespace masq
