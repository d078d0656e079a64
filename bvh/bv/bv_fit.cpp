#include "bvh/bv/bv_fit.h"
#include "bvh/bounds/bounding_sphere.h"
#include "bvh/bounds/obb_fit.h"
#include "masq/error.h"
#include <algorithm>
#include <cmath>
#include <deque>
#include <numbers>

namespace masq {

namespace {

// Double-rounding margin: every quantity below is a short sum of products, whose
// error is far below 2^-48 times the summed magnitude of its terms.
constexpr double kMargin = 0x1p-48;

float up(double value, double magnitude) { return round_up(value + kMargin * magnitude); }
float down(double value, double magnitude) { return round_down(value - kMargin * magnitude); }

// Stores v rounded to fp32 and returns exactly what was stored: every later bound is
// computed about the stored value.
// The volatile is load-bearing: GCC 12 at -O3 vectorised the store and handed back the
// UNROUNDED doubles as "what was stored" (cvtpd2ps stored, the double(float(x)) round
// trip folded away), which tests/test_bv_hierarchy.cpp caught as fp32 volumes 1 ulp
// short of their primitives.
glm::dvec3 store3(float* dst, const glm::dvec3& v) {
  glm::dvec3 back;
  for (int k = 0; k < 3; ++k) {
    volatile float f = static_cast<float>(v[k]);
    dst[k] = f;
    back[k] = double(f);
  }
  return back;
}

std::span<const BallHull> node_hulls(const FlatTree::Node& n, std::span<const BallHull> hulls) {
  return hulls.subspan(std::size_t(n.first), std::size_t(n.size));
}

// Upper bound of max over the hulls of |x - c| for an fp32-exact centre c.
float ball_radius_about(std::span<const BallHull> hulls, const glm::dvec3& c) {
  double r = 0, mag = 0;
  for (const BallHull& h : hulls)
    for (int i = 0; i < h.count; ++i) {
      double d = glm::length(h.centre[i] - c) + h.radius[i];
      if (d > r) r = d, mag = d + glm::length(glm::abs(h.centre[i])) + glm::length(glm::abs(c));
    }
  return up(r, mag);
}

// [min, max] of dot(a, x - c) over the hulls, rounded outward (a, c fp32-exact).
std::pair<float, float> slab_about(std::span<const BallHull> hulls, const glm::dvec3& a, const glm::dvec3& c) {
  double lo = INFINITY, hi = -INFINITY, mag = 0;
  double la = glm::length(a);
  for (const BallHull& h : hulls)
    for (int i = 0; i < h.count; ++i) {
      glm::dvec3 v = h.centre[i] - c;
      double s = glm::dot(a, v);
      lo = std::min(lo, s - h.radius[i] * la);
      hi = std::max(hi, s + h.radius[i] * la);
      mag = std::max(mag, glm::dot(glm::abs(a), glm::abs(v)) + glm::dot(glm::abs(a), glm::abs(h.centre[i])) +
                              glm::dot(glm::abs(a), glm::abs(c)) + h.radius[i] * la);
    }
  return {down(lo, mag), up(hi, mag)};
}

template <class N>
void link(N& node, const FlatTree::Node& t) {
  node.child = t.child;
  node.count = t.count;
}

} // namespace

FlatTree flatten(const BinaryBvh& bvh) {
  FlatTree t;
  t.order.assign(bvh.order.begin(), bvh.order.end());
  if (bvh.nodes.empty()) return t;
  // Subtree ranges (post-order over the source tree).
  std::vector<std::pair<int, int>> range(bvh.nodes.size());
  std::vector<int> stack = {0}, post;
  while (!stack.empty()) {
    int i = stack.back();
    stack.pop_back();
    post.push_back(i);
    const BinaryNode& n = bvh.nodes[std::size_t(i)];
    if (!n.is_leaf()) stack.push_back(n.left), stack.push_back(n.right);
  }
  for (auto it = post.rbegin(); it != post.rend(); ++it) {
    const BinaryNode& n = bvh.nodes[std::size_t(*it)];
    if (n.is_leaf()) {
      range[std::size_t(*it)] = {n.first, n.count};
      continue;
    }
    auto [lf, lc] = range[std::size_t(n.left)];
    auto [rf, rc] = range[std::size_t(n.right)];
    if (rf != lf + lc && lf != rf + rc) throw Error("bv: subtree primitives are not contiguous in leaf order");
    range[std::size_t(*it)] = {std::min(lf, rf), lc + rc};
  }
  // Breadth-first layout: the two children of a node are allocated together.
  struct Item {
    int src, dst, depth;
  };
  std::deque<Item> queue = {{0, 0, 1}};
  t.nodes.resize(1);
  t.nodes[0].parent = -1;
  while (!queue.empty()) {
    Item it = queue.front();
    queue.pop_front();
    const BinaryNode& n = bvh.nodes[std::size_t(it.src)];
    FlatTree::Node& d = t.nodes[std::size_t(it.dst)];
    d.first = range[std::size_t(it.src)].first;
    d.size = range[std::size_t(it.src)].second;
    t.depth = std::max(t.depth, it.depth);
    if (n.is_leaf()) {
      d.child = n.first;
      d.count = n.count;
      continue;
    }
    int c = int(t.nodes.size());
    d.child = c;
    d.count = 0;
    t.nodes.resize(t.nodes.size() + 2);
    t.nodes[std::size_t(c)].parent = it.dst;
    t.nodes[std::size_t(c) + 1].parent = it.dst;
    queue.push_back({n.left, c, it.depth + 1});
    queue.push_back({n.right, c + 1, it.depth + 1});
  }
  return t;
}

std::vector<kernel::BvNodeAabb> fit_aabb_nodes(const FlatTree& t, std::span<const BallHull> hulls) {
  std::vector<kernel::BvNodeAabb> out(t.nodes.size());
  for (std::size_t i = 0; i < t.nodes.size(); ++i) {
    Aabb b;
    for (const BallHull& h : node_hulls(t.nodes[i], hulls)) b.grow(hull_box(h));
    double mag = std::max(glm::length(glm::abs(b.lo)), glm::length(glm::abs(b.hi)));
    for (int k = 0; k < 3; ++k) {
      out[i].lo[k] = down(b.lo[k], mag);
      out[i].hi[k] = up(b.hi[k], mag);
    }
    link(out[i], t.nodes[i]);
  }
  return out;
}

std::vector<kernel::BvNodeSphere> fit_sphere_nodes(const FlatTree& t, std::span<const BallHull> hulls) {
  std::vector<kernel::BvNodeSphere> out(t.nodes.size());
  for (std::size_t i = 0; i < t.nodes.size(); ++i) {
    std::span<const BallHull> h = node_hulls(t.nodes[i], hulls);
    glm::dvec3 c = store3(out[i].center, epos26_ball(h).centre);
    out[i].radius = ball_radius_about(h, c);
    link(out[i], t.nodes[i]);
  }
  return out;
}

std::vector<kernel::BvNodeObb> fit_obb_nodes(const FlatTree& t, std::span<const BallHull> hulls) {
  std::vector<kernel::BvNodeObb> out(t.nodes.size());
  for (std::size_t i = 0; i < t.nodes.size(); ++i) {
    std::span<const BallHull> h = node_hulls(t.nodes[i], hulls);
    ObbFrame f = fit_obb(h);
    glm::dvec3 c = store3(out[i].center, f.centre);
    float* axis[3] = {out[i].axis0, out[i].axis1, out[i].axis2};
    float* half[3] = {&out[i].half0, &out[i].half1, &out[i].half2};
    for (int k = 0; k < 3; ++k) {
      glm::dvec3 a = store3(axis[k], f.axes[k]);
      auto [lo, hi] = slab_about(h, a, c);
      *half[k] = std::max(-lo, hi); // fp32 negation is exact
    }
    link(out[i], t.nodes[i]);
  }
  return out;
}

double scb_area(double radius, double e, double f) {
  const double pi = std::numbers::pi;
  double hi = std::clamp(e, -radius, radius), lo = std::clamp(f, -radius, radius);
  if (hi < lo) return 0.0;
  // Spherical zone between the planes plus the two discs the planes cut.
  return 2.0 * pi * radius * (hi - lo) + pi * (radius * radius - hi * hi) + pi * (radius * radius - lo * lo);
}

std::vector<kernel::BvNodeScb> fit_scb_nodes(const FlatTree& t, std::span<const BallHull> hulls, double scb_p) {
  std::vector<kernel::BvNodeScb> out(t.nodes.size());
  std::vector<glm::dvec3> normal(t.nodes.size(), glm::dvec3(0.0));
  // Breadth-first layout: parents come before their children.
  for (std::size_t i = 0; i < t.nodes.size(); ++i) {
    std::span<const BallHull> h = node_hulls(t.nodes[i], hulls);
    glm::dvec3 c = store3(out[i].center, epos26_ball(h).centre);
    float r = ball_radius_about(h, c);
    ObbFrame f = fit_obb(h);
    const int parent = t.nodes[i].parent;
    double best = INFINITY;
    for (int k = 0; k < 3; ++k) {
      float stored[3];
      glm::dvec3 n = store3(stored, f.axes[k]);
      auto [lo, hi] = slab_about(h, n, c);
      double ln = glm::length(n);
      double area = scb_area(r, hi / ln, lo / ln);
      // Reduced area: favour slabs orthogonal to the parent's (they cut what it did not).
      double ortho = parent >= 0 ? 1.0 - std::fabs(glm::dot(n / ln, normal[std::size_t(parent)])) : 0.0;
      double reduced = (1.0 - scb_p * ortho) * area;
      if (reduced < best) {
        best = reduced;
        normal[i] = n / ln;
        store3(out[i].normal, n);
        out[i].e = hi;
        out[i].f = lo;
      }
    }
    out[i].radius = r;
    link(out[i], t.nodes[i]);
  }
  return out;
}

} // namespace masq
