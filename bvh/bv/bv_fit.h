// Fitting the fp32 node volumes of a binary hierarchy (kernels/bv_layout.h) to the
// world-space hulls of each node's primitives. Everything is computed in double and
// every stored float is rounded outward (with a margin for the double arithmetic), so
// the volume AS STORED contains the exact hulls; tests/test_bv_hierarchy.cpp checks it.
#pragma once
#include "bvh/binary/binned_sah.h"
#include "bvh/bounds/prim_bounds.h"
#include "kernels/layout.h"
#include <span>
#include <vector>

namespace masq {

// A binary tree laid out for the kernels: node 0 the root, children of an inner node
// adjacent (left at child, right at child + 1), leaves pointing into `order` (leaf
// order). first/count: every node's range of `order` (subtrees are contiguous).
struct FlatTree {
  struct Node {
    int child = -1; // inner: index of the left child; leaf: first entry of order
    int count = 0;  // leaf: > 0
    int first = 0;  // the subtree's range in order
    int size = 0;
    int parent = -1;
  };
  std::vector<Node> nodes;
  std::vector<int> order; // primitive ids
  int depth = 0;
};

// Throws masq::Error if a subtree's primitives are not contiguous in bvh.order.
FlatTree flatten(const BinaryBvh& bvh);

// hulls_in_order[i]: hull of primitive order[i]. scb_p: the slab-choice weight p.
std::vector<kernel::BvNodeAabb> fit_aabb_nodes(const FlatTree& t, std::span<const BallHull> hulls_in_order);
std::vector<kernel::BvNodeSphere> fit_sphere_nodes(const FlatTree& t, std::span<const BallHull> hulls_in_order);
std::vector<kernel::BvNodeObb> fit_obb_nodes(const FlatTree& t, std::span<const BallHull> hulls_in_order);
std::vector<kernel::BvNodeScb> fit_scb_nodes(const FlatTree& t, std::span<const BallHull> hulls_in_order, double scb_p);

// Surface area of a slab cut ball (unit normal; slab offsets e >= f from the centre).
double scb_area(double radius, double e, double f);

} // namespace masq
