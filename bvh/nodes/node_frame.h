// The frames of oriented wide nodes (node format o4, kernels/layout.h OrientedNode4):
// which rotation a node gets, and its children's boxes in that frame. After Woop et al.
// 2014 (orientation from the primitives' directions) and Kern et al. 2025's DOBB-BVH
// (one rotation per wide node, converted from an AABB wide BVH, kept where the SAH in
// the node's frame gains).
#pragma once
#include "bvh/bounds/aabb.h"
#include "bvh/bounds/prim_bounds.h"
#include "bvh/binary/binned_sah.h"
#include <array>
#include <cstdint>
#include <functional>
#include <span>
#include <vector>

namespace masq {

// A node's frame x' = M x with M = q / 128 (row-major signed bytes), exact in fp32 and
// in double; not orthonormal, only close to a rotation. Axis-aligned: the identity.
struct NodeFrame {
  bool oriented = false;
  std::array<std::int8_t, 9> q{};
  glm::dvec3 row(int k) const; // row k of M
  glm::dmat3 box_to_space() const; // M^-1: a box in the frame back to the node's space
};

// The quantised frame whose rows are the given orthonormal axes (glm columns), each
// entry rounded to the nearest of -127..127 over 128.
NodeFrame quantised_frame(const glm::dmat3& axes);

// The box of hulls in each of up to kMaxFrameBoxes frames (out[i]: frames[i]'s), from one
// pass over the hulls: per row m_k of a frame, the hulls' extent along m_k, in double,
// widened by the double evaluation's own rounding bound (then rounded outward to fp32 by
// whoever stores it, so the stored box contains the exact one). Throws masq::Error for
// more frames or a size mismatch.
inline constexpr std::size_t kMaxFrameBoxes = 3; // a node's two candidates and its parent's
void frame_boxes(std::span<const BallHull> hulls, std::span<const NodeFrame> frames, std::span<Aabb> out);

// The hull of reference `ref` (a primitive id for a BLAS) in the space its tree's
// boxes are in.
using RefHull = std::function<BallHull(std::int32_t ref)>;

// A node is rotated when its children's boxes in the best candidate frame cost at most
// this fraction of the axis-aligned boxes' (the rotation is paid on every visit:
// docs/kernels.md, "Node formats", measures it).
inline constexpr double kOrientedGain = 0.85;

// A node keeps its parent's rotation when that frame's children's boxes cost at most
// this factor times the best candidate's: the cpu's o4 walk then reuses the ray it
// already rotated into that frame (kernels/node_formats.h, O4RayCache), where a new
// frame costs its nine entries' decode, two products and three divisions per ray. On
// the default bundle's nearly parallel strands, about half of the rotated nodes a
// camera ray visited needed a new frame before.
inline constexpr double kFrameReuse = 1.1;

// What an o4 collapse rotates its nodes by: every reference's hull and the gain above
// (+inf: every node rotated, the format's numerical worst case that the stress suite
// runs).
struct NodeFraming {
  RefHull hull_of;
  double gain = kOrientedGain;
};

// Chooses the frames of a binary BVH's wide nodes. The references' hulls are laid out
// in the tree's depth-first leaf order, so every subtree's are one contiguous span
// (bvh.order need not be: reinsertion moves subtrees).
class NodeFramer {
public:
  NodeFramer(const BinaryBvh& bvh, const std::vector<std::int32_t>& ref_ids, const NodeFraming& framing);

  struct Choice {
    NodeFrame frame;          // identity when the node stays axis aligned
    std::vector<Aabb> boxes;  // oriented: each child's box in the frame (double)
  };
  // The frame of a wide node whose children are the binary nodes `kids`: the candidate
  // (the principal frame of the primitives' directions, the best-fit OBB of their
  // hulls) whose children's boxes cost least, kept only when that cost is at most the
  // framing's gain times the axis-aligned boxes'. Cost is summed surface area times
  // primitives, per child (the SAH's leaf estimate). `parent`, the frame of the node
  // above (null at the root), is taken instead when it passes the same gain test and
  // costs at most kFrameReuse times that choice.
  Choice choose(const std::vector<int>& kids, const NodeFrame* parent = nullptr) const;
  // The references under binary node `node`.
  std::size_t references(int node) const {
    return std::size_t(range_[std::size_t(node)].second - range_[std::size_t(node)].first);
  }

private:
  std::span<const BallHull> subtree(int node) const;
  const BinaryBvh& bvh_;
  double gain_;
  std::vector<BallHull> hulls_;            // depth-first leaf order
  std::vector<std::pair<int, int>> range_; // per binary node: its [first, end) in hulls_
};

} // namespace masq
