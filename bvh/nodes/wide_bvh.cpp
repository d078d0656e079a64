#include "bvh/nodes/wide_bvh.h"
#include "bvh/binary/parallel.h"
#include "bvh/nodes/node_frame.h"
#include "bvh/nodes/quant_node.h"
#include "scenes/reserve_more.h"
#include "kernels/variants.h"
#include "masq/error.h"
#include <algorithm>
#include <iterator>
#include <array>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <type_traits>

namespace masq {

namespace {

// A wide node's binary children, at most the widest format's eight, in place (a vector
// each was a heap allocation per wide node).
struct Kids {
  std::array<int, 8> at{};
  int size = 0;
  const int* begin() const { return at.data(); }
  const int* end() const { return at.data() + size; }
  operator std::span<const int>() const { return {at.data(), std::size_t(size)}; }
};

// Children of a wide node of `width`: repeatedly open the inner child of largest area,
// as long as the node keeps at most max_inner inner children (each one beyond the first
// is a stack entry that waits while the nearest is traversed).
Kids gather(const BinaryBvh& bvh, int binary, int width, int max_inner) {
  if (width > int(Kids{}.at.size())) throw Error("bvh: wide nodes of " + std::to_string(width) + " children");
  Kids kids;
  kids.at[0] = bvh.nodes[binary].left;
  kids.at[1] = bvh.nodes[binary].right;
  kids.size = 2;
  auto is_inner = [&](int n) { return !bvh.nodes[n].is_leaf(); };
  while (kids.size < width) {
    int inner = int(std::count_if(kids.begin(), kids.end(), is_inner));
    int best = -1;
    double best_area = -1.0;
    for (int i = 0; i < kids.size; ++i) {
      const BinaryNode& n = bvh.nodes[kids.at[std::size_t(i)]];
      if (n.is_leaf()) continue;
      const double area = n.box.area();
      if (area <= best_area) continue;
      if (inner - 1 + int(is_inner(n.left)) + int(is_inner(n.right)) > max_inner) continue;
      best = i;
      best_area = area;
    }
    if (best < 0) break;
    int open = kids.at[std::size_t(best)];
    kids.at[std::size_t(best)] = bvh.nodes[open].left;
    kids.at[std::size_t(kids.size++)] = bvh.nodes[open].right;
  }
  return kids;
}
Kids leaf_root() {
  Kids k;
  k.size = 1; // binary node 0
  return k;
}
std::vector<int> as_vector(const Kids& k) { return {k.begin(), k.end()}; }

// Stack entries below a node. bound: as if popping it pushed all `inner` children (its
// own entry not counted); the nearest is popped next while the other inner-1 wait below
// it. The same bound holds for any width, since a node's children are all pushed at
// once; the collapse keeps it within MASQ_STACK_MAX. kernel: what the kernels push
// (kernels/traverse.h): they hold the nearest inner child instead of pushing it, so only
// the other inner-1 wait, and a node whose children are leaves pushes nothing. Both take
// the neediest child as the nearest (the worst case some ray meets).
struct StackNeedOf {
  int bound = 0;
  int kernel = 0;
};
StackNeedOf stack_need(int inner, StackNeedOf deepest) {
  if (inner == 0) return {};
  return {inner - 1 + std::max(1, deepest.bound), inner - 1 + deepest.kernel};
}
StackNeedOf deeper(StackNeedOf a, StackNeedOf b) { return {std::max(a.bound, b.bound), std::max(a.kernel, b.kernel)}; }

struct Common {
  const BinaryBvh& bvh;
  int max_inner; // inner children per node (gather)
  const std::vector<std::int32_t>& ref_ids;
  HugePageVector<std::int32_t>& refs;
  WideBvhInfo info;
  double root_area = 0;

  int emit_leaf_refs(const BinaryNode& leaf) {
    int first = int(refs.size());
    for (int i = leaf.first; i < leaf.first + leaf.count; ++i) refs.push_back(ref_ids[bvh.order[i]]);
    ++info.leaves;
    info.sah_cost += leaf.box.area() / root_area * leaf.count;
    return first;
  }
  void count_node(const Aabb& box, int depth) {
    ++info.nodes;
    info.depth = std::max(info.depth, depth);
    info.sah_cost += box.area() / root_area;
  }
};

// o4: a wide node's children and frame, chosen before any node is emitted. A node's
// frame depends only on its children and its parent's frame, so sibling subtrees are
// planned at once; the emission that follows is the serial depth-first one, and each
// frame is the one a serial collapse chooses.
struct FramePlan {
  std::vector<int> kids;
  NodeFramer::Choice choice;
  std::vector<std::unique_ptr<FramePlan>> child; // per slot: an inner child's plan (else null)
};

// A node over fewer references than this plans its subtrees on one thread: a task per
// node of a few dozen hulls cost more than its frame choice.
constexpr std::size_t kParallelFramePlan = 2048;

std::unique_ptr<FramePlan> plan_frames(const NodeFramer& framer, const BinaryBvh& bvh, std::vector<int> kids,
                                       const NodeFrame* parent, int width, int max_inner) {
  auto p = std::make_unique<FramePlan>();
  p->kids = std::move(kids);
  p->choice = framer.choose(p->kids, parent);
  p->child.resize(p->kids.size());
  std::vector<int> inner;
  std::size_t references = 0;
  for (int s = 0; s < int(p->kids.size()); ++s) {
    references += framer.references(p->kids[std::size_t(s)]);
    if (!bvh.nodes[std::size_t(p->kids[std::size_t(s)])].is_leaf()) inner.push_back(s);
  }
  auto plan_slot = [&](int s) {
    p->child[std::size_t(s)] = plan_frames(framer, bvh, as_vector(gather(bvh, p->kids[std::size_t(s)], width, max_inner)),
                                           &p->choice.frame, width, max_inner);
  };
  if (references >= kParallelFramePlan && inner.size() > 1) {
    parallel_chunks(inner.size(), 1, [&](std::size_t a, std::size_t b) {
      for (std::size_t i = a; i < b; ++i) plan_slot(inner[i]);
    });
  } else {
    for (int s : inner) plan_slot(s);
  }
  return p;
}

// The float boxes of a node: the node itself (w4, w8) or, for o4, its WideNode part.
kernel::WideNode& boxes_of(kernel::WideNode& n) { return n; }
kernel::WideNode8& boxes_of(kernel::WideNode8& n) { return n; }
kernel::WideNode& boxes_of(kernel::OrientedNode4& n) { return n.boxes; }

// The o4 node's frame words (kernels/layout.h OrientedNode4).
void set_frame(kernel::OrientedNode4& w, const NodeFrame& f) {
  w.oriented = f.oriented ? 1u : 0u;
  for (int j = 0; j < 9; ++j)
    w.rot[j / 4] |= std::uint32_t(std::uint8_t(f.q[std::size_t(j)])) << (8 * (j % 4));
}

// w4, w8 and o4: float boxes rounded outward, children emitted depth first. o4 nodes
// take the framer's choice; without a framer every o4 node is axis aligned.
template <class Node, int Width>
struct FloatCollapser : Common {
  HugePageVector<Node>& nodes;

  template <class Boxes>
  static void set_box(Boxes& w, int slot, const Aabb& b) {
    w.lo_x[slot] = round_down(b.lo.x);
    w.lo_y[slot] = round_down(b.lo.y);
    w.lo_z[slot] = round_down(b.lo.z);
    w.hi_x[slot] = round_up(b.hi.x);
    w.hi_y[slot] = round_up(b.hi.y);
    w.hi_z[slot] = round_up(b.hi.z);
  }

  // Emits the wide node for a list of binary children; returns {index, stack need}.
  // plan: the node's frame plan (o4 with a framer; else null, and every o4 node is
  // axis aligned).
  std::pair<int, StackNeedOf> emit(std::span<const int> kids, const Aabb& box, int depth,
                                   const FramePlan* plan = nullptr) {
    int index = int(nodes.size());
    nodes.push_back({});
    count_node(box, depth);
    Node node{};
    auto& w = boxes_of(node);
    const NodeFramer::Choice* framed = plan ? &plan->choice : nullptr;
    if constexpr (std::is_same_v<Node, kernel::OrientedNode4>) {
      if (framed) set_frame(node, framed->frame);
      if (framed && framed->frame.oriented) {
        ++info.oriented;
        if (depth == 1) info.root_oriented = true;
      }
    }
    for (int s = 0; s < Width; ++s) w.count[s] = -1;
    int inner = 0;
    StackNeedOf deepest;
    for (int s = 0; s < int(kids.size()); ++s) {
      const BinaryNode& c = bvh.nodes[kids[s]];
      set_box(w, s, framed && framed->frame.oriented ? framed->boxes[std::size_t(s)] : c.box);
      if (c.is_leaf()) {
        w.child[s] = emit_leaf_refs(c);
        w.count[s] = c.count;
      } else {
        const FramePlan* sub = plan ? plan->child[std::size_t(s)].get() : nullptr;
        auto [child, need] =
            sub ? emit(sub->kids, c.box, depth + 1, sub) : emit(gather(bvh, kids[s], Width, max_inner), c.box, depth + 1);
        w.child[s] = child;
        w.count[s] = 0;
        ++inner;
        deepest = deeper(deepest, need);
      }
    }
    nodes[index] = node;
    return {index, stack_need(inner, deepest)};
  }
};

// q8: a node's inner children are allocated side by side before any is filled, and its
// leaves' references side by side, so one base index each addresses them.
struct QuantCollapser : Common {
  HugePageVector<kernel::QuantNode8>& nodes;

  // Fills node `index` (already allocated); returns its stack need.
  StackNeedOf fill(int index, std::span<const int> kids, int depth) {
    Aabb box;
    for (int k : kids) box.grow(bvh.nodes[k].box);
    count_node(box, depth);
    QuantFrame frame = quant_frame(box);
    std::array<QuantBox, 8> qboxes{};
    std::array<std::uint8_t, 8> meta{};
    const int ref_base = int(refs.size());
    std::vector<int> inner_kids;
    for (int s = 0; s < int(kids.size()); ++s) {
      const BinaryNode& c = bvh.nodes[kids[s]];
      qboxes[std::size_t(s)] = quantize_box(frame, c.box);
      if (c.is_leaf()) {
        if (c.count > MASQ_Q8_MAX_LEAF)
          throw Error("bvh: a leaf of " + std::to_string(c.count) + " references exceeds the q8 node format's " +
                      std::to_string(MASQ_Q8_MAX_LEAF) + "; use node format w4 or w8");
        emit_leaf_refs(c);
        meta[std::size_t(s)] = std::uint8_t(c.count);
      } else {
        meta[std::size_t(s)] = std::uint8_t(MASQ_Q8_INNER);
        inner_kids.push_back(kids[s]);
      }
    }
    const int child_base = int(nodes.size());
    nodes.resize(nodes.size() + inner_kids.size());
    StackNeedOf deepest;
    for (std::size_t j = 0; j < inner_kids.size(); ++j)
      deepest = deeper(deepest, fill(child_base + int(j), gather(bvh, inner_kids[j], 8, max_inner), depth + 1));
    nodes[std::size_t(index)] = pack_quant_node(frame, qboxes, meta, child_base, ref_base);
    return stack_need(int(inner_kids.size()), deepest);
  }
};

void check_stack(WideBvhInfo& info, StackNeedOf need) {
  info.stack_need = 1 + need.bound;
  info.kernel_stack = need.kernel;
  if (info.stack_need > MASQ_STACK_MAX)
    throw Error("bvh: traversal would need a stack of " + std::to_string(info.stack_need) +
                " entries; the kernels have at most " + std::to_string(MASQ_STACK_MAX));
}

// One collapse with at most max_inner inner children per node; {info, stack need}.
template <class Node, int Width>
WideBvhInfo collapse_float(const BinaryBvh& bvh, const std::vector<std::int32_t>& ref_ids, HugePageVector<Node>& nodes,
                           HugePageVector<std::int32_t>& refs, int max_inner, StackNeedOf& need,
                           const NodeFramer* framer = nullptr) {
  FloatCollapser<Node, Width> c{{bvh, max_inner, ref_ids, refs, {}}, nodes};
  const BinaryNode& root = bvh.nodes[0];
  c.root_area = std::max(root.box.area(), 1e-300);
  // A root that is itself a leaf becomes a wide node with one leaf slot.
  const Kids kids = root.is_leaf() ? leaf_root() : gather(bvh, 0, Width, max_inner);
  std::unique_ptr<FramePlan> plan = framer ? plan_frames(*framer, bvh, as_vector(kids), nullptr, Width, max_inner) : nullptr;
  auto [index, n] = c.emit(kids, root.box, 1, plan.get());
  c.info.root = index;
  need = n;
  return c.info;
}

WideBvhInfo collapse_quant(const BinaryBvh& bvh, const std::vector<std::int32_t>& ref_ids,
                           HugePageVector<kernel::QuantNode8>& nodes, HugePageVector<std::int32_t>& refs, int max_inner,
                           StackNeedOf& need) {
  QuantCollapser c{{bvh, max_inner, ref_ids, refs, {}}, nodes};
  const BinaryNode& root = bvh.nodes[0];
  c.root_area = std::max(root.box.area(), 1e-300);
  const Kids kids = root.is_leaf() ? leaf_root() : gather(bvh, 0, 8, max_inner);
  int index = int(nodes.size());
  nodes.emplace_back();
  need = c.fill(index, kids, 1);
  c.info.root = index;
  return c.info;
}

// Each waiting sibling is a stack entry, so a full 8-wide node on every level of a deep
// tree needs up to 7 entries per level where a 4-wide one needs 3. When the worst case
// exceeds the kernels' stack, the collapse is redone with fewer inner children per node
// (6, then 4 like w4, 3, 2: leaf slots stay free); the node arrays are rolled back.
template <class Node, class Collapse>
WideBvhInfo collapse_within_stack(const BinaryBvh& bvh, int width, HugePageVector<Node>& nodes,
                                  HugePageVector<std::int32_t>& refs, Collapse collapse) {
  if (bvh.nodes.empty()) return {};
  const std::size_t nodes0 = nodes.size(), refs0 = refs.size();
  // Room for the most a collapse writes (a wide node per binary inner node at most, each
  // reference once), so that the arrays do not regrow through copies of every size on
  // the way, each on pages faulted in afresh (perf: 6% of a build of Ratboy's capsules).
  // Growth stays geometric when BLAS after BLAS is appended to the same arrays.
  reserve_more(nodes, bvh.nodes.size() / 2 + 1);
  reserve_more(refs, bvh.order.size());
  StackNeedOf need;
  WideBvhInfo info;
  for (int max_inner : {8, 6, 4, 3, 2}) {
    if (max_inner > width) continue;
    nodes.resize(nodes0);
    refs.resize(refs0);
    info = collapse(max_inner, need);
    info.max_inner = max_inner;
    if (1 + need.bound <= MASQ_STACK_MAX) break;
  }
  check_stack(info, need);
  return info;
}

template <class Node, int Width>
WideBvhInfo append_float(const BinaryBvh& bvh, const std::vector<std::int32_t>& ref_ids, HugePageVector<Node>& nodes,
                         HugePageVector<std::int32_t>& refs, const NodeFramer* framer = nullptr) {
  return collapse_within_stack(bvh, Width, nodes, refs, [&](int max_inner, StackNeedOf& need) {
    return collapse_float<Node, Width>(bvh, ref_ids, nodes, refs, max_inner, need, framer);
  });
}

WideBvhInfo append_oriented(const BinaryBvh& bvh, const std::vector<std::int32_t>& ref_ids, PackedScene& ps,
                            const NodeFraming* framing) {
  std::optional<NodeFramer> framer;
  if (framing && framing->hull_of && !bvh.nodes.empty()) framer.emplace(bvh, ref_ids, *framing);
  return append_float<kernel::OrientedNode4, MASQ_WIDTH>(bvh, ref_ids, ps.onodes, ps.refs,
                                                          framer ? &*framer : nullptr);
}

WideBvhInfo append_quant(const BinaryBvh& bvh, const std::vector<std::int32_t>& ref_ids,
                         HugePageVector<kernel::QuantNode8>& nodes, HugePageVector<std::int32_t>& refs) {
  return collapse_within_stack(bvh, 8, nodes, refs, [&](int max_inner, StackNeedOf& need) {
    return collapse_quant(bvh, ref_ids, nodes, refs, max_inner, need);
  });
}

template <class Node, int Width>
void float_slots(const Node& n, NodeSlots& out, const NodeFrame& frame = {}) {
  for (int s = 0; s < Width; ++s) {
    NodeSlot slot;
    slot.child = n.child[s];
    slot.count = n.count[s];
    slot.box.lo = {n.lo_x[s], n.lo_y[s], n.lo_z[s]};
    slot.box.hi = {n.hi_x[s], n.hi_y[s], n.hi_z[s]};
    slot.frame = frame;
    out.push_back(slot);
  }
}

} // namespace

WideBvhInfo append_wide_bvh(const BinaryBvh& bvh, const std::vector<std::int32_t>& ref_ids,
                            HugePageVector<kernel::WideNode>& nodes, HugePageVector<std::int32_t>& refs) {
  return append_float<kernel::WideNode, MASQ_WIDTH>(bvh, ref_ids, nodes, refs);
}

WideBvhInfo append_bvh_nodes(const BinaryBvh& bvh, const std::vector<std::int32_t>& ref_ids, NodeFormat format,
                             PackedScene& ps, const NodeFraming* framing) {
  switch (format) {
    case NodeFormat::O4: return append_oriented(bvh, ref_ids, ps, framing);
    case NodeFormat::W8: return append_float<kernel::WideNode8, MASQ_WIDTH8>(bvh, ref_ids, ps.nodes8, ps.refs);
    case NodeFormat::Q8: return append_quant(bvh, ref_ids, ps.qnodes, ps.refs);
    case NodeFormat::W4: break;
  }
  return append_wide_bvh(bvh, ref_ids, ps.nodes, ps.refs);
}

CollapsedBvh collapse_bvh(const BinaryBvh& bvh, const std::vector<std::int32_t>& ref_ids, NodeFormat format) {
  CollapsedBvh c;
  c.format = format;
  switch (format) {
    case NodeFormat::O4: c.info = append_float<kernel::OrientedNode4, MASQ_WIDTH>(bvh, ref_ids, c.onodes, c.refs); break;
    case NodeFormat::W8: c.info = append_float<kernel::WideNode8, MASQ_WIDTH8>(bvh, ref_ids, c.nodes8, c.refs); break;
    case NodeFormat::Q8: c.info = append_quant(bvh, ref_ids, c.qnodes, c.refs); break;
    case NodeFormat::W4: c.info = append_float<kernel::WideNode, MASQ_WIDTH>(bvh, ref_ids, c.nodes, c.refs); break;
  }
  return c;
}

namespace {

// A float node's slots moved: an inner child's node index by node_base, a leaf's first
// reference by ref_base; empty slots (count < 0) keep their zero.
template <class Boxes>
void move_slots(Boxes& w, std::int32_t node_base, std::int32_t ref_base) {
  for (std::size_t s = 0; s < std::size(w.count); ++s)
    if (w.count[s] == 0) w.child[s] += node_base;
    else if (w.count[s] > 0) w.child[s] += ref_base;
}

// from's nodes written to to[at ...], each moved.
template <class Node, class Move>
void place_moved(const HugePageVector<Node>& from, HugePageVector<Node>& to, std::size_t at, Move move) {
  for (std::size_t i = 0; i < from.size(); ++i) {
    Node n = from[i];
    move(n);
    to[at + i] = n;
  }
}

// body(c's node array, ps's node array of that format).
template <class Body>
void with_node_arrays(const CollapsedBvh& c, PackedScene& ps, Body body) {
  switch (c.format) {
    case NodeFormat::W4: return body(c.nodes, ps.nodes);
    case NodeFormat::W8: return body(c.nodes8, ps.nodes8);
    case NodeFormat::O4: return body(c.onodes, ps.onodes);
    case NodeFormat::Q8: return body(c.qnodes, ps.qnodes);
  }
}

} // namespace

std::size_t collapsed_nodes(const CollapsedBvh& c) {
  // collapse_bvh fills its format's array alone.
  return c.nodes.size() + c.nodes8.size() + c.onodes.size() + c.qnodes.size();
}

void grow_node_arrays(PackedScene& ps, std::size_t nodes, std::size_t refs) {
  switch (ps.features.nodes) {
    case NodeFormat::W4: ps.nodes.resize(ps.nodes.size() + nodes); break;
    case NodeFormat::W8: ps.nodes8.resize(ps.nodes8.size() + nodes); break;
    case NodeFormat::O4: ps.onodes.resize(ps.onodes.size() + nodes); break;
    case NodeFormat::Q8: ps.qnodes.resize(ps.qnodes.size() + nodes); break;
  }
  ps.refs.resize(ps.refs.size() + refs);
}

WideBvhInfo place_collapsed(const CollapsedBvh& c, PackedScene& ps, std::size_t node_at, std::size_t ref_at) {
  if (c.format != ps.features.nodes) throw Error("bvh: a collapsed BVH of another node format than the scene's");
  WideBvhInfo info = c.info;
  if (info.root < 0) return info;
  const std::int32_t node_base = std::int32_t(node_at), ref_base = std::int32_t(ref_at);
  auto move = [&](auto& n) {
    using Node = std::decay_t<decltype(n)>;
    if constexpr (std::is_same_v<Node, kernel::QuantNode8>) {
      n.child_base += node_base;
      n.ref_base += ref_base;
    } else {
      move_slots(boxes_of(n), node_base, ref_base);
    }
  };
  with_node_arrays(c, ps, [&](const auto& from, auto& to) { place_moved(from, to, node_at, move); });
  std::copy(c.refs.begin(), c.refs.end(), ps.refs.begin() + std::ptrdiff_t(ref_at));
  info.root += node_base;
  return info;
}

NodeSlots node_slots(const PackedScene& ps, std::int32_t node) {
  NodeSlots out;
  const std::size_t i = std::size_t(node);
  switch (ps.features.nodes) {
    case NodeFormat::W4: float_slots<kernel::WideNode, MASQ_WIDTH>(ps.nodes.at(i), out); break;
    case NodeFormat::W8: float_slots<kernel::WideNode8, MASQ_WIDTH8>(ps.nodes8.at(i), out); break;
    case NodeFormat::O4: {
      const kernel::OrientedNode4& n = ps.onodes.at(i);
      NodeFrame f;
      f.oriented = n.oriented != 0;
      for (int j = 0; j < 9; ++j) f.q[std::size_t(j)] = std::int8_t((n.rot[j / 4] >> (8 * (j % 4))) & 255u);
      float_slots<kernel::WideNode, MASQ_WIDTH>(n.boxes, out, f);
      break;
    }
    case NodeFormat::Q8: {
      const kernel::QuantNode8& n = ps.qnodes.at(i);
      auto byte = [](const std::uint32_t* words, int s) { return (words[s / 4] >> (8 * (s % 4))) & 255u; };
      int next_child = n.child_base, next_ref = n.ref_base;
      for (int s = 0; s < MASQ_WIDTH8; ++s) {
        NodeSlot slot;
        unsigned m = byte(n.meta, s);
        if (m == MASQ_Q8_INNER) {
          slot.child = next_child++;
          slot.count = 0;
        } else if (m != 0) {
          slot.child = next_ref;
          slot.count = int(m);
          next_ref += int(m);
        }
        const std::uint32_t* lo[3] = {n.qlo_x, n.qlo_y, n.qlo_z};
        const std::uint32_t* hi[3] = {n.qhi_x, n.qhi_y, n.qhi_z};
        for (int k = 0; k < 3; ++k) {
          int e = int((n.exps >> (8 * k)) & 255u);
          slot.box.lo[k] = quant_decode(n.origin[k], e, byte(lo[k], s));
          slot.box.hi[k] = quant_decode(n.origin[k], e, byte(hi[k], s));
        }
        out.push_back(slot);
      }
      break;
    }
  }
  return out;
}

} // namespace masq
