#include "bvh/nodes/node_frame.h"
#include "bvh/binary/parallel.h"
#include "bvh/bounds/obb_fit.h"
#include "kernels/layout.h"
#include "masq/error.h"
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <string>

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

void frame_boxes(std::span<const BallHull> hulls, std::span<const NodeFrame> frames, std::span<Aabb> out) {
  if (frames.size() > kMaxFrameBoxes || out.size() != frames.size())
    throw Error("frame_boxes: " + std::to_string(frames.size()) + " frames (at most " +
                std::to_string(kMaxFrameBoxes) + "), " + std::to_string(out.size()) + " boxes");
  // Every frame's three rows in one pass over the balls, each row's minimum, maximum and
  // magnitude taken in ball order (a large subtree's hulls are read once, not once a row).
  constexpr std::size_t kRows = 3 * kMaxFrameBoxes;
  const std::size_t rows = 3 * frames.size();
  std::array<glm::dvec3, kRows> m{}, am{};
  std::array<double, kRows> len{}, lo{}, hi{}, mag{};
  for (std::size_t j = 0; j < rows; ++j) {
    m[j] = frames[j / 3].row(int(j % 3));
    am[j] = glm::abs(m[j]);
    len[j] = glm::length(m[j]);
    lo[j] = INFINITY, hi[j] = -INFINITY, mag[j] = 0;
  }
  for (const BallHull& h : hulls)
    for (int i = 0; i < h.count; ++i) {
      const glm::dvec3 ac = glm::abs(h.centre[i]);
      for (std::size_t j = 0; j < rows; ++j) {
        double c = glm::dot(m[j], h.centre[i]), r = h.radius[i] * len[j];
        lo[j] = std::min(lo[j], c - r);
        hi[j] = std::max(hi[j], c + r);
        mag[j] = std::max(mag[j], glm::dot(am[j], ac) + r);
      }
    }
  for (std::size_t j = 0; j < rows; ++j) {
    // Three products, two sums, the length and the radius term: 8 roundings of at most
    // mag's size, each within 2^-53 relative.
    const double slack = 8.0 * 0x1p-53 * mag[j];
    out[j / 3].lo[int(j % 3)] = lo[j] - slack;
    out[j / 3].hi[int(j % 3)] = hi[j] + slack;
  }
}

NodeFramer::NodeFramer(const BinaryBvh& bvh, const std::vector<std::int32_t>& ref_ids, const NodeFraming& framing)
    : bvh_(bvh), gain_(framing.gain), range_(bvh.nodes.size()) {
  const RefHull& hull_of = framing.hull_of;
  if (bvh.nodes.empty()) return;
  // Depth first, left before right, so each subtree's leaves are consecutive: first
  // every node's range and the leaves in that order, then the hulls into their slots on
  // all threads (one array, sized once: growing it copied and faulted it repeatedly).
  std::vector<int> leaves;
  int size = 0;
  std::vector<std::pair<int, bool>> stack{{0, false}};
  while (!stack.empty()) {
    auto [n, done] = stack.back();
    stack.pop_back();
    const BinaryNode& bn = bvh.nodes[std::size_t(n)];
    if (bn.is_leaf()) {
      range_[std::size_t(n)] = {size, size + bn.count};
      size += bn.count;
      leaves.push_back(n);
    } else if (!done) {
      range_[std::size_t(n)].first = size;
      stack.push_back({n, true});
      stack.push_back({bn.right, false});
      stack.push_back({bn.left, false});
    } else {
      range_[std::size_t(n)].second = size;
    }
  }
  hulls_.resize(std::size_t(size));
  parallel_chunks(leaves.size(), 256, [&](std::size_t l0, std::size_t l1) {
    for (std::size_t l = l0; l < l1; ++l) {
      const BinaryNode& bn = bvh.nodes[std::size_t(leaves[l])];
      int at = range_[std::size_t(leaves[l])].first;
      for (int i = bn.first; i < bn.first + bn.count; ++i)
        hulls_[std::size_t(at++)] = hull_of(ref_ids[std::size_t(bvh.order[std::size_t(i)])]);
    }
  });
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
  // The frames to price: the candidates, then the parent's (priced whether or not it
  // is needed below, so each child's hulls are read once for all of them).
  std::array<NodeFrame, kMaxFrameBoxes> frames;
  std::size_t candidates = 0;
  glm::dmat3 axes;
  if (direction_frame(all, axes)) frames[candidates++] = quantised_frame(axes);
  frames[candidates++] = quantised_frame(fit_obb(all).axes);
  const bool with_parent = parent && parent->oriented;
  const std::size_t n_frames = candidates + (with_parent ? 1 : 0);
  if (with_parent) frames[candidates] = *parent;
  // The children's boxes in each frame, and what each frame's boxes cost (summed in
  // child order).
  std::array<std::vector<Aabb>, kMaxFrameBoxes> boxes;
  std::array<double, kMaxFrameBoxes> cost{};
  std::array<Aabb, kMaxFrameBoxes> kid_boxes;
  for (int k : kids) {
    std::span<const BallHull> h = subtree(k);
    frame_boxes(h, std::span<const NodeFrame>(frames.data(), n_frames), std::span<Aabb>(kid_boxes.data(), n_frames));
    for (std::size_t f = 0; f < n_frames; ++f) {
      boxes[f].push_back(kid_boxes[f]);
      cost[f] += framed_area(kid_boxes[f], frames[f]) * double(h.size());
    }
  }
  // gain +inf: any candidate (inf * 0 for a node of empty boxes would be NaN).
  const double gain_cost = std::isinf(gain_) ? INFINITY : gain_ * aligned;
  double best_cost = gain_cost;
  for (std::size_t f = 0; f < candidates; ++f) {
    if (cost[f] < best_cost || (std::isinf(best_cost) && !best.frame.oriented)) {
      best_cost = cost[f];
      best.frame = frames[f];
      best.boxes = boxes[f];
    }
  }
  if (with_parent && parent->q != best.frame.q) {
    const double parent_cost = cost[candidates];
    bool passes = std::isinf(gain_) || parent_cost <= gain_cost;
    if (passes && (!best.frame.oriented || parent_cost <= kFrameReuse * best_cost)) {
      best.frame = *parent;
      best.boxes = std::move(boxes[candidates]);
    }
  }
  return best;
}

} // namespace masq
