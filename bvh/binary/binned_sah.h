// Binary BVH by binned SAH (Wald 2007): centroid bins per axis, best of the bin planes.
#pragma once
#include "bvh/bounds/aabb.h"
#include "scenes/huge_page_vector.h"
#include <span>
#include <vector>

namespace masq {

struct SahOptions {
  int bins = 16;
  int max_leaf_size = 4;    // a leaf never holds more unless primitives cannot be split
  double traversal_cost = 1.0;
  double intersection_cost = 1.0;
  // A leaf's intersection cost counts blocks of this many primitives (Embree's SAH block
  // size): 4 prices a leaf of 1-4 primitives as one four-lane test, as the cpu backend
  // runs capsules (kernels/capsule_simd_cpp.h); 1 prices each primitive.
  int leaf_block = 1;
};

struct BinaryNode {
  Aabb box;
  int left = -1;  // inner: child indices; leaf: -1
  int right = -1;
  int first = 0;  // leaf: range in BinaryBvh::order
  int count = 0;  // leaf: > 0
  bool is_leaf() const { return count > 0; }
};

struct BinaryBvh {
  // (On huge pages when large: scenes/huge_page_vector.h.)
  HugePageVector<BinaryNode> nodes; // nodes[0] is the root (when any)
  HugePageVector<int> order;        // primitive ids in leaf order
};

BinaryBvh build_binned_sah(std::span<const Aabb> boxes, const SahOptions& opt = {});

// The trees build_binned_sah builds with each of traversal_costs in place of
// opt.traversal_cost (out[i]: traversal_costs[i]'s, the same bytes), from one binning of
// each node: the bin planes do not depend on C_t, only where a tree stops splitting does,
// so the trees share every node above their leaves. On one thread (auto's cluster
// shapes, whose BLAS differ in the leaf price alone: bvh/twolevel/cluster_blas.h).
std::vector<BinaryBvh> build_binned_sah_costs(std::span<const Aabb> boxes, const SahOptions& opt,
                                              std::span<const double> traversal_costs);

} // namespace masq
