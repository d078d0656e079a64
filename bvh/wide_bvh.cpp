#include "bvh/wide_bvh.h"
#include "kernels/variants.h"
#include "scenes/error.h"
#include <algorithm>

namespace masq {

namespace {

struct Collapser {
  const BinaryBvh& bvh;
  const std::vector<std::int32_t>& ref_ids;
  std::vector<kernel::WideNode>& nodes;
  std::vector<std::int32_t>& refs;
  WideBvhInfo info;
  double root_area = 0;

  // Children of a wide node: repeatedly open the inner child of largest area.
  std::vector<int> gather(int binary) const {
    std::vector<int> kids{bvh.nodes[binary].left, bvh.nodes[binary].right};
    while (int(kids.size()) < MASQ_WIDTH) {
      int best = -1;
      double best_area = -1.0;
      for (int i = 0; i < int(kids.size()); ++i) {
        const BinaryNode& n = bvh.nodes[kids[i]];
        if (!n.is_leaf() && n.box.area() > best_area) {
          best = i;
          best_area = n.box.area();
        }
      }
      if (best < 0) break;
      int open = kids[best];
      kids[best] = bvh.nodes[open].left;
      kids.push_back(bvh.nodes[open].right);
    }
    return kids;
  }

  static void set_box(kernel::WideNode& w, int slot, const Aabb& b) {
    w.lo_x[slot] = round_down(b.lo.x);
    w.lo_y[slot] = round_down(b.lo.y);
    w.lo_z[slot] = round_down(b.lo.z);
    w.hi_x[slot] = round_up(b.hi.x);
    w.hi_y[slot] = round_up(b.hi.y);
    w.hi_z[slot] = round_up(b.hi.z);
  }

  int emit_leaf_refs(const BinaryNode& leaf) {
    int first = int(refs.size());
    for (int i = leaf.first; i < leaf.first + leaf.count; ++i) refs.push_back(ref_ids[bvh.order[i]]);
    ++info.leaves;
    info.sah_cost += leaf.box.area() / root_area * leaf.count;
    return first;
  }

  // Emits the wide node for a list of binary children; returns {index, stack need}.
  std::pair<int, int> emit(const std::vector<int>& kids, const Aabb& box, int depth) {
    int index = int(nodes.size());
    nodes.push_back({});
    ++info.nodes;
    info.depth = std::max(info.depth, depth);
    info.sah_cost += box.area() / root_area;
    kernel::WideNode w{};
    for (int s = 0; s < MASQ_WIDTH; ++s) w.count[s] = -1;
    int inner = 0, deepest = 0;
    for (int s = 0; s < int(kids.size()); ++s) {
      const BinaryNode& c = bvh.nodes[kids[s]];
      set_box(w, s, c.box);
      if (c.is_leaf()) {
        w.child[s] = emit_leaf_refs(c);
        w.count[s] = c.count;
      } else {
        auto [child, need] = emit(gather(kids[s]), c.box, depth + 1);
        w.child[s] = child;
        w.count[s] = 0;
        ++inner;
        deepest = std::max(deepest, need);
      }
    }
    nodes[index] = w;
    // Popping this node pushes `inner` entries; the nearest is popped next while the
    // other inner-1 wait below it.
    return {index, inner == 0 ? 0 : inner - 1 + std::max(1, deepest)};
  }
};

} // namespace

WideBvhInfo append_wide_bvh(const BinaryBvh& bvh, const std::vector<std::int32_t>& ref_ids,
                            std::vector<kernel::WideNode>& nodes, std::vector<std::int32_t>& refs) {
  Collapser c{bvh, ref_ids, nodes, refs, {}};
  if (bvh.nodes.empty()) return c.info;
  const BinaryNode& root = bvh.nodes[0];
  c.root_area = std::max(root.box.area(), 1e-300);
  // A root that is itself a leaf becomes a wide node with one leaf slot.
  std::vector<int> kids = root.is_leaf() ? std::vector<int>{0} : c.gather(0);
  auto [index, need] = c.emit(kids, root.box, 1);
  c.info.root = index;
  c.info.stack_need = 1 + need;
  if (c.info.stack_need > MASQ_STACK_SIZE)
    throw Error("bvh: traversal would need a stack of " + std::to_string(c.info.stack_need) +
                " entries; the kernels have " + std::to_string(MASQ_STACK_SIZE));
  return c.info;
}

} // namespace masq
