// Collapse a binary BVH into wide nodes of one node format (w4, w8, q8 or o4; see
// kernels/layout.h and docs/kernels.md) and append them, in the GPU layout, to the node
// array shared by the TLAS and every BLAS.
#pragma once
#include <array>
#include "bvh/binary/binned_sah.h"
#include "bvh/nodes/node_frame.h"
#include "bvh/packed_scene.h"
#include "kernels/layout.h"
#include <cstdint>
#include <vector>

namespace masq {

struct WideBvhInfo {
  std::int32_t root = -1;  // index in the node array
  std::size_t nodes = 0;
  std::size_t leaves = 0;
  double sah_cost = 0;     // traversal 1 per wide node visit, intersection 1 per reference
  int depth = 0;           // wide levels
  int stack_need = 0;      // worst-case stack entries if every inner child were pushed (<= MASQ_STACK_MAX)
  int kernel_stack = 0;    // worst-case entries the kernels push (they hold the nearest child): <= stack_need - 1
  int max_inner = 0;       // inner children per node the collapse allowed (< width: capped to fit the stack)
  std::size_t oriented = 0; // o4: nodes with a rotated frame
  bool root_oriented = false; // o4: the root among them (its padding needs a bound from above: a TLAS)
};

// Appends to the array of `format` in `ps` (ps.nodes, ps.nodes8, ps.qnodes or
// ps.onodes) and leaf references to ps.refs as ref_ids[order[i]] (e.g. primitive or
// instance ids). o4: the framing gives each reference's hull, from which each node's
// frame is chosen (bvh/nodes/node_frame.h); without it every node stays axis aligned. Throws
// masq::Error if traversal would need more than the kernel's fixed stack even with two
// inner children per node, or (q8) a leaf holds more than MASQ_Q8_MAX_LEAF references.
WideBvhInfo append_bvh_nodes(const BinaryBvh& bvh, const std::vector<std::int32_t>& ref_ids, NodeFormat format,
                             PackedScene& ps, const NodeFraming* framing = nullptr);

// A BVH collapsed on its own, its indices from 0: what append_bvh_nodes (without a
// framing) would append, made where it cannot append yet (the cluster BLAS, collapsed
// on all threads and appended in cluster order; bvh/twolevel/cluster_blas.cpp).
struct CollapsedBvh {
  NodeFormat format = NodeFormat::W4;
  HugePageVector<kernel::WideNode> nodes;        // w4
  HugePageVector<kernel::WideNode8> nodes8;      // w8
  HugePageVector<kernel::QuantNode8> qnodes;     // q8
  HugePageVector<kernel::OrientedNode4> onodes;  // o4 (every node axis aligned)
  HugePageVector<std::int32_t> refs;
  WideBvhInfo info;
};
CollapsedBvh collapse_bvh(const BinaryBvh& bvh, const std::vector<std::int32_t>& ref_ids, NodeFormat format);
// The nodes c holds.
std::size_t collapsed_nodes(const CollapsedBvh& c);
// Room for that many more nodes (of ps's format) and references at the ends of ps's arrays.
void grow_node_arrays(PackedScene& ps, std::size_t nodes, std::size_t refs);
// Writes c into ps's arrays (c's format must be ps's) from node node_at and reference
// ref_at on, within room the caller made, its node and reference indices moved there: the
// bytes append_bvh_nodes would have appended at those ends. Returns c's info with the
// root so moved. Collapsed BVHs placed at disjoint ranges may be written at once.
WideBvhInfo place_collapsed(const CollapsedBvh& c, PackedScene& ps, std::size_t node_at, std::size_t ref_at);

// The w4 case on bare arrays.
WideBvhInfo append_wide_bvh(const BinaryBvh& bvh, const std::vector<std::int32_t>& ref_ids,
                            HugePageVector<kernel::WideNode>& nodes, HugePageVector<std::int32_t>& refs);

// One slot of a node of any format, decoded as the kernels decode it (host walks:
// the rayquery backend's cluster members, tests). count > 0: leaf of count references
// from child; 0: inner node child; < 0: empty.
struct NodeSlot {
  std::int32_t child = -1;
  std::int32_t count = -1;
  Aabb box; // the box the kernels test (q8: decoded; o4: in the node's frame)
  NodeFrame frame; // o4: the frame the box is in (x' = M x); else the identity
};
// A node's slots (at most MASQ_WIDTH8, the widest format's), held in place: the host walks
// (the cost model's, the cpu backend's leaf copy) decode every node of a structure, and
// a vector per node was most of their time.
class NodeSlots {
 public:
  void push_back(const NodeSlot& s) { slot_[std::size_t(n_++)] = s; }
  const NodeSlot* begin() const { return slot_.data(); }
  const NodeSlot* end() const { return slot_.data() + n_; }
  std::size_t size() const { return std::size_t(n_); }
  const NodeSlot& operator[](std::size_t i) const { return slot_[i]; }

 private:
  std::array<NodeSlot, MASQ_WIDTH8> slot_{};
  int n_ = 0;
};
NodeSlots node_slots(const PackedScene& ps, std::int32_t node);

} // namespace masq
