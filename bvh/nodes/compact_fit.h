// The compact masquerade entry's fit (compact_instance.h), in stages: what
// compact_instance.cpp (the entries' interface) and compact_fit_lanes.cpp (the stages
// four primitives at a time) share. Why the fit is conservative: compact_fit.cpp.
#pragma once
#include "bvh/bounds/obb.h"
#include "bvh/bounds/prim_bounds.h"
#include "bvh/nodes/compact_instance.h" // kMasqDecodeRelError
#include "kernels/layout.h"
#include <array>
#include <cstdint>

namespace masq::compact_fit {

// A unit quaternion's components as 16-bit integers: q_k = round(32767 u_k).
inline constexpr std::int64_t kQuatScale = 32767;

// The largest bfloat16 <= x (bits of its fp32), or 0 when that is not a positive normal
// number (x too small or too large for the form).
std::uint32_t bf16_down(double x);
double bf16_value(std::uint32_t bits);
// A 32-bit word's signed 16-bit halves, read and written.
std::int32_t half_i16(std::uint32_t word, int hi);
std::uint32_t pack_i16(std::int64_t lo, std::int64_t hi);

// N = |q|^2 R(q), exactly (as the kernel's integer arithmetic): n[col][row], glm order.
struct QuatMatrix {
  glm::dmat3 n{0.0};
  double norm2 = 0; // |q|^2
};
QuatMatrix quat_matrix(std::int64_t x, std::int64_t y, std::int64_t z, std::int64_t w);

// Scale sigma_i of an entry, as the kernel decodes it.
double decoded_scale(const kernel::MasqInstance& c, int i);
// The decoded map of an entry whose quaternion's matrix is q.
Affine3 decode_with(const QuatMatrix& q, const kernel::MasqInstance& c);

// The hull's support in world space along v and -v: h(L^T v) + v . T and
// h(-L^T v) - v . T (exact for its balls' ellipsoids; negating v negates L^T v and v . T
// exactly, so these are the bits of evaluating each direction on its own).
BallHull::Pair world_support_pair(const BallHull& h, const Affine3& xf, const glm::dvec3& v);

// One primitive's fit in progress. compact_masquerades takes up to four primitives
// through the stages together: a fit is one long chain of square roots and divisions
// (axes, quaternion, supports, scales, inverse), and most stages run as four lanes of one
// vector register (compact_fit_lanes.cpp), a primitive a lane.
struct CompactFit {
  BallHull h;
  glm::dmat3 axes{1.0}; // the object OBB's (primitive_obb_axes)
  glm::dvec3 a0{0.0};   // the first world axis
  std::array<std::int64_t, 4> qi{};
  QuatMatrix q;
  Aabb exact; // the hull's world box
  glm::dvec3 reach{0.0}, centre{0.0}, half{0.0};
  kernel::MasqInstance c{}; // t as fitted; the rest packed at the end
  std::array<std::uint32_t, 3> sigma{};
  bool live = true; // false: the compact form cannot hold this primitive
};

// The stages in order; each lane stage takes n <= 4 fits (f[0..n)) at once.
// 1. The hulls of prims[0..n) and their object OBBs' axes (primitive_obb_axes), and the
//    first world axes.
void fit_axes_lanes(CompactFit* const* f, int n, const Geometry& g, const std::int32_t* prims, const Affine3& xf);
// 2. The world axes made orthonormal, as a quaternion of 16-bit integers and its matrix.
void fit_rotation_lanes(CompactFit* const* f, int n, const Affine3& xf);
// 3. The hull's world box, centre and half extents along the decoded axes, then each
//    axis's scale and translation (fit_scale's first try; a lane it does not fit runs
//    fit_scale on its own).
void fit_extent_lanes(CompactFit* const* f, int n, const Affine3& xf);
// Stage 1 for one fit: its hull (throws for a primitive of radius 0), then its axes.
void fit_hull(CompactFit& f, const Geometry& g, std::size_t prim);
void fit_axes(CompactFit& f, const Geometry& g, const Affine3& xf);
// Axis i's bfloat16 scale and fp32 translation, proved conservative; false where none fits.
bool fit_scale(CompactFit& f, int i, const Affine3& xf);
// 4. complete_masquerade_box(decode_with(q, c), exact) of the packed entries: *out[l]
//    gets lane l's box, ok[l] false where it is empty or not finite.
void complete_lanes(CompactFit* const* f, int n, MasqueradeBox* const* out, bool* ok);

} // namespace masq::compact_fit
