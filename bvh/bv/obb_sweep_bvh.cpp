#include "bvh/bv/obb_sweep_bvh.h"
#include "bvh/bounds/obb_fit.h"
#include <algorithm>
#include <numeric>

namespace masq {

namespace {

// Box in a frame's coordinates (3 intervals) and its surface area.
struct FrameBox {
  glm::dvec3 lo{INFINITY}, hi{-INFINITY};
  void grow(const FrameBox& b) {
    lo = glm::min(lo, b.lo);
    hi = glm::max(hi, b.hi);
  }
  double area() const {
    glm::dvec3 e = glm::max(hi - lo, glm::dvec3(0.0));
    return 2.0 * (e.x * e.y + e.y * e.z + e.z * e.x);
  }
};

glm::dvec3 hull_centroid(const BallHull& h) {
  glm::dvec3 c{0.0};
  for (int i = 0; i < h.count; ++i) c += h.centre[i];
  return h.count > 0 ? c / double(h.count) : c;
}

struct SweepBuilder {
  const std::vector<BallHull>& hulls;
  const SahOptions& opt;
  BinaryBvh out;
  std::vector<glm::dvec3> centroid;

  int build(int begin, int end, int depth) {
    int index = int(out.nodes.size());
    out.nodes.emplace_back();
    const int n = end - begin;
    std::vector<BallHull> local;
    local.reserve(static_cast<std::size_t>(n));
    for (int i = begin; i < end; ++i) local.push_back(hulls[std::size_t(out.order[std::size_t(i)])]);
    Aabb world;
    for (const BallHull& h : local) world.grow(hull_box(h));
    out.nodes[std::size_t(index)].box = world;
    if (n <= 1) return leaf(index, begin, n);

    ObbFrame frame = fit_obb(local);
    // Per primitive: its box in the node's frame.
    std::vector<FrameBox> fb(static_cast<std::size_t>(n));
    for (int i = 0; i < n; ++i)
      for (int k = 0; k < 3; ++k) {
        Interval iv = hull_extent(std::span<const BallHull>(&local[std::size_t(i)], 1), frame.axes[k]);
        fb[std::size_t(i)].lo[k] = iv.lo;
        fb[std::size_t(i)].hi[k] = iv.hi;
      }
    FrameBox all;
    for (const FrameBox& b : fb) all.grow(b);
    const double parent_area = all.area();

    double best_cost = INFINITY;
    int best_axis = -1, best_split = n / 2;
    std::vector<int> idx(static_cast<std::size_t>(n)), best_idx;
    std::vector<double> right_area(static_cast<std::size_t>(n));
    if (depth < kBvMedianDepth) {
      for (int k = 0; k < 3; ++k) {
        std::iota(idx.begin(), idx.end(), 0);
        std::vector<double> key(static_cast<std::size_t>(n));
        for (int i = 0; i < n; ++i)
          key[std::size_t(i)] = glm::dot(frame.axes[k], centroid[std::size_t(out.order[std::size_t(begin + i)])]);
        std::stable_sort(idx.begin(), idx.end(), [&](int a, int b) { return key[std::size_t(a)] < key[std::size_t(b)]; });
        FrameBox acc;
        for (int i = n - 1; i >= 1; --i) {
          acc.grow(fb[std::size_t(idx[std::size_t(i)])]);
          right_area[std::size_t(i)] = acc.area();
        }
        acc = FrameBox{};
        for (int i = 1; i < n; ++i) {
          acc.grow(fb[std::size_t(idx[std::size_t(i - 1)])]);
          double cost = acc.area() * i + right_area[std::size_t(i)] * (n - i);
          if (cost < best_cost) best_cost = cost, best_axis = k, best_split = i, best_idx = idx;
        }
      }
    }
    if (best_axis >= 0 && n <= opt.max_leaf_size) {
      double split = opt.traversal_cost + opt.intersection_cost * best_cost / std::max(parent_area, 1e-300);
      if (!(split < opt.intersection_cost * n)) return leaf(index, begin, n);
    }
    if (best_axis < 0) { // median split along the frame's longest side
      int k = 0;
      for (int a = 1; a < 3; ++a)
        if (frame.half[a] > frame.half[k]) k = a;
      best_idx.resize(static_cast<std::size_t>(n));
      std::iota(best_idx.begin(), best_idx.end(), 0);
      std::vector<double> key(static_cast<std::size_t>(n));
      for (int i = 0; i < n; ++i)
        key[std::size_t(i)] = glm::dot(frame.axes[k], centroid[std::size_t(out.order[std::size_t(begin + i)])]);
      std::stable_sort(best_idx.begin(), best_idx.end(), [&](int a, int b) { return key[std::size_t(a)] < key[std::size_t(b)]; });
      best_split = n / 2;
    }
    std::vector<int> reordered(static_cast<std::size_t>(n));
    for (int i = 0; i < n; ++i) reordered[std::size_t(i)] = out.order[std::size_t(begin + best_idx[std::size_t(i)])];
    std::copy(reordered.begin(), reordered.end(), out.order.begin() + begin);
    local.clear();
    local.shrink_to_fit();
    int l = build(begin, begin + best_split, depth + 1);
    int r = build(begin + best_split, end, depth + 1);
    out.nodes[std::size_t(index)].left = l;
    out.nodes[std::size_t(index)].right = r;
    return index;
  }

  int leaf(int index, int begin, int n) {
    BinaryNode& nd = out.nodes[std::size_t(index)];
    nd.first = begin;
    nd.count = n;
    return index;
  }
};

int depth_of(const BinaryBvh& b, int node) {
  const BinaryNode& n = b.nodes[std::size_t(node)];
  if (n.is_leaf()) return 1;
  return 1 + std::max(depth_of(b, n.left), depth_of(b, n.right));
}

} // namespace

BinaryBvh build_obb_sweep(const std::vector<BallHull>& hulls, const SahOptions& opt) {
  SweepBuilder b{hulls, opt, {}, {}};
  if (hulls.empty()) return {};
  b.out.order.resize(hulls.size());
  std::iota(b.out.order.begin(), b.out.order.end(), 0);
  b.centroid.reserve(hulls.size());
  for (const BallHull& h : hulls) b.centroid.push_back(hull_centroid(h));
  b.build(0, int(hulls.size()), 1);
  return std::move(b.out);
}

int binary_depth(const BinaryBvh& bvh) { return bvh.nodes.empty() ? 0 : depth_of(bvh, 0); }

} // namespace masq
