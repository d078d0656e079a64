// Insertion-based optimisation of a binary BVH (Bittner, Hapala & Havran 2013, "Fast
// Insertion-Based Optimization of Bounding Volume Hierarchies"): take the inner nodes
// whose boxes are large over a small child, remove each with its parent (the sibling
// takes the parent's place) and reinsert its two children, each as the sibling of the
// node where it adds the least SAH cost, found by a branch-and-bound search over the
// tree. A move that raised the cost is undone, so the cost never rises; passes stop
// when one gains less than min_gain of the cost or after max_passes. Leaves and their
// references are kept as they are: it works the same for a TLAS over instance boxes
// and for a BLAS (SBVH's duplicate references included).
#pragma once
#include "bvh/binary/binned_sah.h"

namespace masq {

struct ReinsertOptions {
  int max_passes = 8;         // rounds of remove-and-reinsert
  double batch = 0.25;        // fraction of the inner nodes moved per pass, largest measure first
  double min_gain = 1e-3;     // stop when a pass lowers the cost by less than this fraction
  // A pass that leaves the tree more than this many levels deeper than the input is
  // undone and ends the optimisation: the kernels' traversal stack is fixed
  // (MASQ_STACK_SIZE), and moves can deepen a tree (random boxes: 26 -> 34 levels).
  int max_extra_depth = 4;
};

struct ReinsertStats {
  double cost_before = 0, cost_after = 0; // binary SAH cost, as binary_sah_cost
  int passes = 0;          // passes kept
  int depth_before = 0, depth_after = 0; // binary levels
  std::size_t moves = 0; // subtrees put somewhere else
};

// SAH cost of a binary BVH relative to its root area: traversal_cost per inner node
// visit, intersection_cost per reference in a leaf.
double binary_sah_cost(const BinaryBvh& bvh, const SahOptions& sah = {});
// Levels of a binary BVH (a lone leaf: 1).
int binary_depth_of(const BinaryBvh& bvh);

// The optimised tree: same leaves (first/count into the same `order` contents, which
// is rewritten in depth-first leaf order), root at index 0, children after parents.
BinaryBvh reinsert_optimize(const BinaryBvh& bvh, const SahOptions& sah = {}, const ReinsertOptions& opt = {},
                            ReinsertStats* stats = nullptr);

} // namespace masq
