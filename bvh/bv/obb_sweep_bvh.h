// The slab-cut-ball paper's top-down build: at every node, fit a tight OBB to the node's
// primitives and choose the partition by a full SAH sweep along each of the OBB's three
// axes, where a side's cost is its primitive count times the surface area of its
// bounding box IN THE NODE'S OBB FRAME. The topology is independent of the bounding
// volume later fitted to each node (bv_fit.h), so every BV type can share it.
#pragma once
#include "bvh/binary/binned_sah.h"
#include "bvh/bounds/prim_bounds.h"
#include <vector>

namespace masq {

// Nodes deeper than this are split at the median count (keeps traversal stacks bounded).
constexpr int kBvMedianDepth = 40;

// hulls[i]: primitive i's world-space hull. BinaryNode::box is the node's world AABB.
BinaryBvh build_obb_sweep(const std::vector<BallHull>& hulls, const SahOptions& opt = {});

// Depth of a binary tree (root = 1).
int binary_depth(const BinaryBvh& bvh);

} // namespace masq
