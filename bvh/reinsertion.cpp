#include "bvh/reinsertion.h"
#include "scenes/error.h"
#include <algorithm>
#include <cmath>
#include <queue>

namespace masq {

double binary_sah_cost(const BinaryBvh& bvh, const SahOptions& sah) {
  if (bvh.nodes.empty()) return 0.0;
  double root = std::max(bvh.nodes[0].box.area(), 1e-300);
  double cost = 0;
  for (const BinaryNode& n : bvh.nodes)
    cost += n.box.area() / root * (n.is_leaf() ? sah.intersection_cost * n.count : sah.traversal_cost);
  return cost;
}

namespace {

struct Tree {
  std::vector<BinaryNode> nodes;
  std::vector<int> parent;
  int root = 0;

  int sibling(int n) const {
    int p = parent[std::size_t(n)];
    return nodes[std::size_t(p)].left == n ? nodes[std::size_t(p)].right : nodes[std::size_t(p)].left;
  }
  void replace_child(int p, int from, int to) {
    BinaryNode& pn = nodes[std::size_t(p)];
    (pn.left == from ? pn.left : pn.right) = to;
    parent[std::size_t(to)] = p;
  }
  // Boxes are exact unions of the children's (min/max do not round), so a subtree
  // put back where it was restores every box bit for bit.
  void refit_from(int n) {
    for (; n >= 0; n = parent[std::size_t(n)]) {
      BinaryNode& x = nodes[std::size_t(n)];
      Aabb b = nodes[std::size_t(x.left)].box;
      b.grow(nodes[std::size_t(x.right)].box);
      x.box = b;
    }
  }

  // Detach subtree n with its parent p; the sibling takes p's place. Returns p (free).
  int remove(int n) {
    int p = parent[std::size_t(n)];
    int s = sibling(n);
    int g = parent[std::size_t(p)];
    if (g < 0) {
      root = s;
      parent[std::size_t(s)] = -1;
    } else {
      replace_child(g, p, s);
      refit_from(g);
    }
    return p;
  }

  // Put n back as the sibling of x, with `p` as their new parent.
  void insert(int n, int x, int p) {
    int g = parent[std::size_t(x)];
    BinaryNode& pn = nodes[std::size_t(p)];
    pn.left = x;
    pn.right = n;
    pn.count = 0;
    parent[std::size_t(x)] = p;
    parent[std::size_t(n)] = p;
    parent[std::size_t(p)] = g;
    if (g < 0) root = p;
    else replace_child(g, x, p);
    refit_from(p);
  }

  // Cost (in area units, times traversal cost) of putting a box b as the sibling of x:
  // the new parent's area plus the growth of every ancestor of x.
  double insertion_cost(int x, const Aabb& b) const {
    Aabb u = nodes[std::size_t(x)].box;
    u.grow(b);
    double c = u.area();
    for (int a = parent[std::size_t(x)]; a >= 0; a = parent[std::size_t(a)]) {
      Aabb ua = nodes[std::size_t(a)].box;
      ua.grow(b);
      c += ua.area() - nodes[std::size_t(a)].box.area();
    }
    return c;
  }

  // Branch and bound (Bittner et al. 2013, section 4.2): nodes in order of their
  // induced cost (the ancestors' growth); a subtree is pruned once its induced cost
  // plus the least possible direct cost (the area of b) reaches the best found.
  int best_position(const Aabb& b, int start, double& best) const {
    int best_x = start;
    best = insertion_cost(start, b);
    double ab = b.area();
    using Entry = std::pair<double, int>;
    std::priority_queue<Entry, std::vector<Entry>, std::greater<>> queue;
    queue.push({0.0, root});
    while (!queue.empty()) {
      auto [induced, x] = queue.top();
      queue.pop();
      if (induced + ab >= best) break;
      const BinaryNode& xn = nodes[std::size_t(x)];
      Aabb u = xn.box;
      u.grow(b);
      double direct = u.area();
      if (induced + direct < best) {
        best = induced + direct;
        best_x = x;
      }
      double child_induced = induced + direct - xn.box.area();
      if (!xn.is_leaf() && child_induced + ab < best) {
        queue.push({child_induced, xn.left});
        queue.push({child_induced, xn.right});
      }
    }
    return best_x;
  }
};

double inner_area_sum(const Tree& t) {
  // Only inner nodes change: leaves keep their boxes and references.
  double s = 0;
  std::vector<int> stack{t.root};
  while (!stack.empty()) {
    int n = stack.back();
    stack.pop_back();
    const BinaryNode& x = t.nodes[std::size_t(n)];
    if (x.is_leaf()) continue;
    s += x.box.area();
    stack.push_back(x.left);
    stack.push_back(x.right);
  }
  return s;
}

// Depth-first copy from the root: children after parents, `order` in leaf order.
BinaryBvh compact(const Tree& t, const BinaryBvh& in) {
  BinaryBvh out;
  out.nodes.reserve(in.nodes.size());
  out.order.reserve(in.order.size());
  std::vector<std::pair<int, int>> stack{{t.root, 0}}; // (tree node, out index)
  out.nodes.push_back({});
  while (!stack.empty()) {
    auto [n, o] = stack.back();
    stack.pop_back();
    const BinaryNode& x = t.nodes[std::size_t(n)];
    out.nodes[std::size_t(o)].box = x.box;
    if (x.is_leaf()) {
      out.nodes[std::size_t(o)].first = int(out.order.size());
      out.nodes[std::size_t(o)].count = x.count;
      for (int i = x.first; i < x.first + x.count; ++i) out.order.push_back(in.order[std::size_t(i)]);
      continue;
    }
    int l = int(out.nodes.size());
    out.nodes.push_back({});
    out.nodes.push_back({});
    out.nodes[std::size_t(o)].left = l;
    out.nodes[std::size_t(o)].right = l + 1;
    stack.push_back({x.right, l + 1});
    stack.push_back({x.left, l});
  }
  return out;
}

} // namespace

BinaryBvh reinsert_optimize(const BinaryBvh& bvh, const SahOptions& sah, const ReinsertOptions& opt,
                            ReinsertStats* stats) {
  if (opt.max_passes < 0 || !(opt.batch > 0.0 && opt.batch <= 1.0))
    throw Error("reinsertion: max_passes must be >= 0 and batch in (0, 1]");
  ReinsertStats st;
  st.cost_before = st.cost_after = binary_sah_cost(bvh, sah);
  if (bvh.nodes.size() < 5) { // fewer than three levels: nothing can move
    if (stats) *stats = st;
    return bvh;
  }
  Tree t{bvh.nodes, std::vector<int>(bvh.nodes.size(), -1), 0};
  for (std::size_t i = 0; i < t.nodes.size(); ++i)
    if (!t.nodes[i].is_leaf()) {
      t.parent[std::size_t(t.nodes[i].left)] = int(i);
      t.parent[std::size_t(t.nodes[i].right)] = int(i);
    }
  double cost = inner_area_sum(t);
  std::vector<std::pair<double, int>> cand;
  for (int pass = 0; pass < opt.max_passes; ++pass) {
    // Candidates (any node below the root's children): by Bittner et al.'s
    // m_min x m_area measure, A(N) * A(N) / min(A(children)) for inner nodes, A(N) for
    // leaves: large boxes, above all those over a small child, are the badly placed ones.
    cand.clear();
    for (std::size_t i = 0; i < t.nodes.size(); ++i) {
      const BinaryNode& x = t.nodes[i];
      int p = t.parent[i];
      if (p < 0 || t.parent[std::size_t(p)] < 0) continue;
      double a = x.box.area();
      if (x.is_leaf()) {
        cand.push_back({a, int(i)});
        continue;
      }
      double kid = std::min(t.nodes[std::size_t(x.left)].box.area(), t.nodes[std::size_t(x.right)].box.area());
      cand.push_back({a * a / std::max(kid, 1e-300 * a + 1e-300), int(i)});
    }
    if (cand.empty()) break;
    std::size_t take = std::max<std::size_t>(1, std::size_t(opt.batch * double(cand.size())));
    take = std::min(take, cand.size());
    std::partial_sort(cand.begin(), cand.begin() + std::ptrdiff_t(take), cand.end(), std::greater<>());
    double before = cost;
    for (std::size_t c = 0; c < take; ++c) {
      int n = cand[c].second;
      int p = t.parent[std::size_t(n)];
      if (p < 0 || t.parent[std::size_t(p)] < 0) continue; // moved next to the root meanwhile
      int s = t.sibling(n);
      int freed = t.remove(n);
      double best = 0;
      int x = t.best_position(t.nodes[std::size_t(n)].box, s, best);
      t.insert(n, x, freed);
      if (x != s) ++st.moves;
    }
    cost = inner_area_sum(t);
    ++st.passes;
    if (!(before - cost > opt.min_gain * before)) break;
  }
  BinaryBvh out = compact(t, bvh);
  st.cost_after = binary_sah_cost(out, sah);
  // Each move is chosen by summed area differences, which round; never hand back a
  // tree that came out (however slightly) worse than the input.
  if (st.cost_after > st.cost_before) {
    st.cost_after = st.cost_before;
    out = bvh;
  }
  if (stats) *stats = st;
  return out;
}

} // namespace masq
