#include "bvh/nodes/node_frame.h"
#include "bvh/bounds/obb_fit.h"
#include "kernels/layout.h"
#include <algorithm>
#include <cmath>
#include <cstddef>

namespace masq {

// The kernels read the o4 node as words (kernels/node_formats.h) at these offsets.
static_assert(offsetof(kernel::OrientedNode4, rot) == 4 * MASQ_O4_ROT);
static_assert(offsetof(kernel::OrientedNode4, oriented) == 4 * MASQ_O4_ORIENTED);
static_assert(offsetof(kernel::WideNode, child) == 4 * 24 && offsetof(kernel::WideNode, count) == 4 * 28);

glm::dvec3 NodeFrame::row(int k) const {
  if (!oriented) return glm::dvec3(k == 0, k == 1, k == 2);
  return glm::dvec3(q[std::size_t(3 * k)], q[std::size_t(3 * k + 1)], q[std::size_t(3 * k + 2)]) / 128.0;
}

glm::dmat3 NodeFrame::box_to_space() const {
  glm::dmat3 m; // glm: m[column][row]
  for (int k = 0; k < 3; ++k)
    for (int j = 0; j < 3; ++j) m[j][k] = row(k)[j];
  return glm::inverse(m);
}

NodeFrame quantised_frame(const glm::dmat3& axes) {
  NodeFrame f;
  f.oriented = true;
  for (int k = 0; k < 3; ++k)
    for (int j = 0; j < 3; ++j)
      f.q[std::size_t(3 * k + j)] = std::int8_t(std::clamp(std::lround(axes[k][j] * 127.0), -127L, 127L));
  return f;
}

Aabb frame_box(std::span<const BallHull> hulls, const NodeFrame& f) {
  Aabb b;
  for (int k = 0; k < 3; ++k) {
    const glm::dvec3 m = f.row(k);
    const glm::dvec3 am = glm::abs(m);
    const double len = glm::length(m);
    double lo = INFINITY, hi = -INFINITY, mag = 0;
    for (const BallHull& h : hulls)
      for (int i = 0; i < h.count; ++i) {
        double c = glm::dot(m, h.centre[i]), r = h.radius[i] * len;
        lo = std::min(lo, c - r);
        hi = std::max(hi, c + r);
        mag = std::max(mag, glm::dot(am, glm::abs(h.centre[i])) + r);
      }
    // Three products, two sums, the length and the radius term: 8 roundings of at most
    // mag's size, each within 2^-53 relative.
    const double slack = 8.0 * 0x1p-53 * mag;
    b.lo[k] = lo - slack;
    b.hi[k] = hi + slack;
  }
  return b;
}

NodeFramer::NodeFramer(const BinaryBvh& bvh, const std::vector<std::int32_t>& ref_ids, const NodeFraming& framing)
    : bvh_(bvh), gain_(framing.gain), range_(bvh.nodes.size()) {
  const RefHull& hull_of = framing.hull_of;
  if (bvh.nodes.empty()) return;
  // Depth first, left before right, so each subtree's leaves are consecutive.
  std::vector<std::pair<int, bool>> stack{{0, false}};
  while (!stack.empty()) {
    auto [n, done] = stack.back();
    stack.pop_back();
    const BinaryNode& bn = bvh.nodes[std::size_t(n)];
    if (bn.is_leaf()) {
      range_[std::size_t(n)].first = int(hulls_.size());
      for (int i = bn.first; i < bn.first + bn.count; ++i)
        hulls_.push_back(hull_of(ref_ids[std::size_t(bvh.order[std::size_t(i)])]));
      range_[std::size_t(n)].second = int(hulls_.size());
    } else if (!done) {
      range_[std::size_t(n)].first = int(hulls_.size());
      stack.push_back({n, true});
      stack.push_back({bn.right, false});
      stack.push_back({bn.left, false});
    } else {
      range_[std::size_t(n)].second = int(hulls_.size());
    }
  }
}

std::span<const BallHull> NodeFramer::subtree(int node) const {
  auto [first, end] = range_[std::size_t(node)];
  return std::span<const BallHull>(hulls_).subspan(std::size_t(first), std::size_t(end - first));
}

namespace {

// A box's surface area in the node's space when its extents are along rows m_k of a
// frame (|m_k| ~ 1: the frame is a rotation scaled by at most 127/128 and rounded).
double framed_area(const Aabb& b, const NodeFrame& f) {
  if (b.empty()) return 0.0;
  glm::dvec3 e = b.hi - b.lo;
  for (int k = 0; k < 3; ++k) e[k] /= glm::length(f.row(k));
  return 2.0 * (e.x * e.y + e.y * e.z + e.z * e.x);
}

// The principal frame of the primitives' directions (first to last ball: a capsule's
// axis, a curve's chord), sign-free: the eigenvectors of sum(v v^T), as columns. False when no hull has a direction (spheres, triangles: the best-fit OBB
// candidate covers them).
bool direction_frame(std::span<const BallHull> hulls, glm::dmat3& axes) {
  glm::dmat3 t(0.0);
  for (const BallHull& h : hulls) {
    if (h.count < 2) continue;
    glm::dvec3 v = h.centre[std::size_t(h.count - 1)] - h.centre[0];
    t += glm::outerProduct(v, v);
  }
  if (!(t[0][0] + t[1][1] + t[2][2] > 0)) return false;
  axes = symmetric_eigenvectors(t);
  return true;
}

} // namespace

NodeFramer::Choice NodeFramer::choose(const std::vector<int>& kids, const NodeFrame* parent) const {
  Choice best;
  double aligned = 0;
  int first = INT32_MAX, end = 0;
  for (int k : kids) {
    const BinaryNode& n = bvh_.nodes[std::size_t(k)];
    int count = range_[std::size_t(k)].second - range_[std::size_t(k)].first;
    aligned += n.box.area() * count;
    first = std::min(first, range_[std::size_t(k)].first);
    end = std::max(end, range_[std::size_t(k)].second);
  }
  const std::span<const BallHull> all = std::span<const BallHull>(hulls_).subspan(std::size_t(first),
                                                                                  std::size_t(end - first));
  std::vector<glm::dmat3> candidates;
  glm::dmat3 axes;
  if (direction_frame(all, axes)) candidates.push_back(axes);
  candidates.push_back(fit_obb(all).axes);
  // The children's boxes in frame f and what they cost.
  auto framed = [&](const NodeFrame& f, std::vector<Aabb>& boxes) {
    double cost = 0;
    for (int k : kids) {
      std::span<const BallHull> h = subtree(k);
      boxes.push_back(frame_box(h, f));
      cost += framed_area(boxes.back(), f) * double(h.size());
    }
    return cost;
  };
  // gain +inf: any candidate (inf * 0 for a node of empty boxes would be NaN).
  const double gain_cost = std::isinf(gain_) ? INFINITY : gain_ * aligned;
  double best_cost = gain_cost;
  for (const glm::dmat3& c : candidates) {
    NodeFrame f = quantised_frame(c);
    std::vector<Aabb> boxes;
    double cost = framed(f, boxes);
    if (cost < best_cost || (std::isinf(best_cost) && !best.frame.oriented)) {
      best_cost = cost;
      best.frame = f;
      best.boxes = std::move(boxes);
    }
  }
  if (parent && parent->oriented && parent->q != best.frame.q) {
    std::vector<Aabb> boxes;
    double cost = framed(*parent, boxes);
    bool passes = std::isinf(gain_) || cost <= gain_cost;
    if (passes && (!best.frame.oriented || cost <= kFrameReuse * best_cost)) {
      best.frame = *parent;
      best.boxes = std::move(boxes);
    }
  }
  return best;
}

} // namespace masq
