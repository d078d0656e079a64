#include "bvh/binary/reinsertion.h"
#include "masq/error.h"
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
  HugePageVector<BinaryNode> nodes;
  std::vector<int> parent;
  int root = 0;
  double total = 0; // summed area of the inner nodes, kept up to date by every edit

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
      total += b.area() - x.box.area();
      x.box = b;
    }
  }

  // Detach subtree n with its parent p; the sibling takes p's place. Returns p, now free.
  int remove(int n) {
    int p = parent[std::size_t(n)];
    int s = sibling(n);
    int g = parent[std::size_t(p)];
    total -= nodes[std::size_t(p)].box.area();
    if (g < 0) {
      root = s;
      parent[std::size_t(s)] = -1;
    } else {
      replace_child(g, p, s);
      refit_from(g);
    }
    parent[std::size_t(n)] = -1;
    return p;
  }

  // Put n back as the sibling of x, with the free node p as their parent.
  void insert(int n, int x, int p) {
    int g = parent[std::size_t(x)];
    BinaryNode& pn = nodes[std::size_t(p)];
    pn.left = x;
    pn.right = n;
    pn.count = 0;
    pn.box = nodes[std::size_t(x)].box;
    pn.box.grow(nodes[std::size_t(n)].box);
    total += pn.box.area();
    parent[std::size_t(x)] = p;
    parent[std::size_t(n)] = p;
    parent[std::size_t(p)] = g;
    if (g < 0) root = p;
    else {
      replace_child(g, x, p);
      refit_from(g);
    }
  }

  // Branch and bound (Bittner et al. 2013, section 4.2) for the node x where adding
  // box b as x's sibling costs least: the new parent's area plus the growth of every
  // ancestor. Nodes come in order of their induced cost (the ancestors' growth); a
  // subtree is pruned once that plus the least possible direct cost (the area of b)
  // reaches the best found.
  int best_position(const Aabb& b) const {
    int best_x = root;
    double best = INFINITY;
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

  // Bittner et al.'s move: take inner node n and its parent out of the tree and
  // reinsert n's two children (the larger first) where each costs least. Undone when
  // the summed inner area went up, so no move raises the cost. Returns true when kept.
  bool move(int n) {
    const double before = total;
    int p = parent[std::size_t(n)];
    int g = parent[std::size_t(p)];
    bool p_left = nodes[std::size_t(g)].left == p, n_left = nodes[std::size_t(p)].left == n;
    int s = sibling(n);
    const int orig_left = nodes[std::size_t(n)].left, orig_right = nodes[std::size_t(n)].right;
    int a = orig_left, b = orig_right;
    if (nodes[std::size_t(a)].box.area() < nodes[std::size_t(b)].box.area()) std::swap(a, b);
    // Out: p goes (s takes its place), then n (its children are loose).
    total -= nodes[std::size_t(p)].box.area() + nodes[std::size_t(n)].box.area();
    replace_child(g, p, s);
    refit_from(g);
    parent[std::size_t(a)] = parent[std::size_t(b)] = -1;
    insert(a, best_position(nodes[std::size_t(a)].box), n);
    insert(b, best_position(nodes[std::size_t(b)].box), p);
    if (total <= before) return true;
    // Undo in reverse order: b and a out again, then n and p back as they were.
    remove(b);
    remove(a);
    BinaryNode& nn = nodes[std::size_t(n)];
    nn.left = orig_left;
    nn.right = orig_right;
    parent[std::size_t(a)] = parent[std::size_t(b)] = n;
    nn.box = nodes[std::size_t(a)].box;
    nn.box.grow(nodes[std::size_t(b)].box);
    BinaryNode& pn = nodes[std::size_t(p)];
    pn.left = n_left ? n : s;
    pn.right = n_left ? s : n;
    parent[std::size_t(n)] = parent[std::size_t(s)] = p;
    pn.box = nodes[std::size_t(n)].box;
    pn.box.grow(nodes[std::size_t(s)].box);
    (p_left ? nodes[std::size_t(g)].left : nodes[std::size_t(g)].right) = p;
    parent[std::size_t(p)] = g;
    total += nn.box.area() + pn.box.area();
    refit_from(g);
    return false;
  }
};

int tree_depth(const Tree& t) {
  int deepest = 0;
  std::vector<std::pair<int, int>> stack{{t.root, 1}};
  while (!stack.empty()) {
    auto [n, d] = stack.back();
    stack.pop_back();
    deepest = std::max(deepest, d);
    const BinaryNode& x = t.nodes[std::size_t(n)];
    if (x.is_leaf()) continue;
    stack.push_back({x.left, d + 1});
    stack.push_back({x.right, d + 1});
  }
  return deepest;
}

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

int binary_depth_of(const BinaryBvh& bvh) {
  if (bvh.nodes.empty()) return 0;
  Tree t{bvh.nodes, {}, 0};
  return tree_depth(t);
}

BinaryBvh reinsert_optimize(const BinaryBvh& bvh, const SahOptions& sah, const ReinsertOptions& opt,
                            ReinsertStats* stats) {
  if (opt.max_passes < 0 || !(opt.batch > 0.0 && opt.batch <= 1.0))
    throw Error("reinsertion: max_passes must be >= 0 and batch in (0, 1]");
  ReinsertStats st;
  st.cost_before = st.cost_after = binary_sah_cost(bvh, sah);
  if (bvh.nodes.size() < 5) { // fewer than three levels: nothing can move
    st.depth_before = st.depth_after = binary_depth_of(bvh);
    if (stats) *stats = st;
    return bvh;
  }
  Tree t{bvh.nodes, std::vector<int>(bvh.nodes.size(), -1), 0};
  for (std::size_t i = 0; i < t.nodes.size(); ++i)
    if (!t.nodes[i].is_leaf()) {
      t.parent[std::size_t(t.nodes[i].left)] = int(i);
      t.parent[std::size_t(t.nodes[i].right)] = int(i);
    }
  t.total = inner_area_sum(t);
  st.depth_before = st.depth_after = tree_depth(t);
  const int depth_cap = st.depth_before + std::max(0, opt.max_extra_depth);
  std::vector<std::pair<double, int>> cand;
  Tree saved;
  for (int pass = 0; pass < opt.max_passes; ++pass) {
    saved = t;
    const std::size_t moves_before = st.moves;
    // Candidates: inner nodes with a grandparent, by Bittner et al.'s
    // m_min x m_area measure A(N) * A(N) / min(A(children)): large boxes, above all
    // those over a small child, are the badly placed ones.
    cand.clear();
    for (std::size_t i = 0; i < t.nodes.size(); ++i) {
      const BinaryNode& x = t.nodes[i];
      int p = t.parent[i];
      if (x.is_leaf() || p < 0 || t.parent[std::size_t(p)] < 0) continue;
      double a = x.box.area();
      double kid = std::min(t.nodes[std::size_t(x.left)].box.area(), t.nodes[std::size_t(x.right)].box.area());
      cand.push_back({a * a / std::max(kid, 1e-300 * a + 1e-300), int(i)});
    }
    if (cand.empty()) break;
    std::size_t take = std::max<std::size_t>(1, std::size_t(opt.batch * double(cand.size())));
    take = std::min(take, cand.size());
    std::partial_sort(cand.begin(), cand.begin() + std::ptrdiff_t(take), cand.end(), std::greater<>());
    double before = t.total;
    for (std::size_t c = 0; c < take; ++c) {
      int n = cand[c].second;
      int p = t.parent[std::size_t(n)];
      if (t.nodes[std::size_t(n)].is_leaf() || p < 0 || t.parent[std::size_t(p)] < 0) continue; // moved meanwhile
      st.moves += t.move(n);
    }
    t.total = inner_area_sum(t); // re-anchor the running sum
    int depth = tree_depth(t);
    if (depth > depth_cap) {
      t = std::move(saved);
      st.moves = moves_before;
      break;
    }
    st.depth_after = depth;
    ++st.passes;
    if (!(before - t.total > opt.min_gain * before)) break;
  }
  BinaryBvh out = compact(t, bvh);
  st.cost_after = binary_sah_cost(out, sah);
  // Each move is chosen by summed area differences, which round; never hand back a
  // tree that came out (however slightly) worse than the input.
  if (st.cost_after > st.cost_before) {
    st.cost_after = st.cost_before;
    st.depth_after = st.depth_before;
    out = bvh;
  }
  if (stats) *stats = st;
  return out;
}

} // namespace masq
