// The compact masquerade entry's fit (compact_fit.h). Why the stored map is conservative:
//  1. The rotation is a quaternion q of 16-bit integers; the kernel forms
//     N = |q|^2 R(q) (the homogeneous formula) in exact integer arithmetic, so the
//     decoded axes are exactly orthonormal whatever q's rounding did. The host refits
//     the box along THOSE axes (support function of the primitive's ball hull), so the
//     quantised rotation costs only the misalignment it causes (~3e-5 rad).
//  2. Scales sigma_i = 1 / (half_i |q|^2) are rounded DOWN to bfloat16: a smaller scale
//     is a larger box (at most one bfloat16 step, 2^-7, per axis).
//  3. The kernel's fp32 decode of entry M_ij = sigma_i N_ji is one int -> float
//     conversion and one product: no addition, so fma contraction or reassociation
//     cannot change it, and no subnormal (|N_ij| >= 1 or N_ij = 0, sigma normal) and
//     no overflow (sigma |q|^2 < FLT_MAX, checked). Correctly rounded, the result is
//     within (1 + u)^2 - 1 < 2.0001 u of M_ij; we allow 8 u (kMasqDecodeRelError), which
//     still holds for a device whose conversion or product is off by an ulp or rounds
//     toward zero (2 u each). At a world point x the unit coordinate k then errs by at
//     most 8 u sum_j |M_kj| |x_j| <= 8 u sum_j |M_kj| X_j, X the hull's largest
//     world coordinates (from its exact world box).
//  4. With t rounded to fp32 as stored, each row is checked in double: the hull's
//     extent max(|h(M_k) + t_k|, |-h(-M_k) + t_k|) plus that decode bound plus a
//     1e-12 relative allowance for the double evaluation itself must be <= 1; a row
//     that fails shrinks its own scale (one bfloat16 step or more) and recomputes t_k.
//     The kernel's padded unit-box test (kernels/box.h) then covers the fp32 ray
//     transform under the decoded fp32 matrix, as for 64-byte instances.
#include "bvh/nodes/compact_fit.h"
#include "masq/error.h"
#include "scenes/prim_table.h"
#include <bit>
#include <cfloat>
#include <cmath>
#include <string>

namespace masq::compact_fit {

std::uint32_t bf16_down(double x) {
  if (!(x > 0.0) || !std::isfinite(x)) return 0;
  std::uint32_t f = std::bit_cast<std::uint32_t>(float(x));
  // float(x) > x: the float below it (f is positive, at most infinity: one step down is
  // the bits less one, as nextafter toward 0 gives, without its library call).
  if (double(std::bit_cast<float>(f)) > x) f -= 1u;
  std::uint32_t b = f & 0xFFFF0000u;
  std::uint32_t e = (b >> 23) & 0xFFu;
  return (e == 0 || e == 255) ? 0 : b;
}

double bf16_value(std::uint32_t bits) { return double(std::bit_cast<float>(bits)); }

std::int32_t half_i16(std::uint32_t word, int hi) {
  std::int32_t v = std::int32_t(hi ? word >> 16 : word & 0xFFFFu);
  return v >= 32768 ? v - 65536 : v;
}

std::uint32_t pack_i16(std::int64_t lo, std::int64_t hi) {
  return (std::uint32_t(lo) & 0xFFFFu) | ((std::uint32_t(hi) & 0xFFFFu) << 16);
}

QuatMatrix quat_matrix(std::int64_t x, std::int64_t y, std::int64_t z, std::int64_t w) {
  QuatMatrix q;
  const std::int64_t xx = x * x, yy = y * y, zz = z * z, ww = w * w;
  const std::int64_t xy = x * y, xz = x * z, yz = y * z, wx = w * x, wy = w * y, wz = w * z;
  const std::int64_t rows[3][3] = {{ww + xx - yy - zz, 2 * (xy - wz), 2 * (xz + wy)},
                                   {2 * (xy + wz), ww - xx + yy - zz, 2 * (yz - wx)},
                                   {2 * (xz - wy), 2 * (yz + wx), ww - xx - yy + zz}};
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) q.n[c][r] = double(rows[r][c]);
  q.norm2 = double(xx + yy + zz + ww);
  return q;
}

BallHull::Pair world_support_pair(const BallHull& h, const Affine3& xf, const glm::dvec3& v) {
  const BallHull::Pair p = h.support_pair(glm::transpose(xf.linear) * v);
  const double shift = glm::dot(v, xf.translation);
  return {p.plus + shift, p.minus - shift};
}

double decoded_scale(const kernel::MasqInstance& c, int i) {
  return bf16_value(i == 0 ? c.s01 << 16 : i == 1 ? c.s01 & 0xFFFF0000u : c.s2_owner & 0xFFFF0000u);
}

Affine3 decode_with(const QuatMatrix& q, const kernel::MasqInstance& c) {
  Affine3 m;
  for (int i = 0; i < 3; ++i) {
    const double sigma = decoded_scale(c, i);
    for (int j = 0; j < 3; ++j) m.linear[j][i] = sigma * q.n[i][j]; // M_ij = sigma_i N_ji
    m.translation[i] = c.t[i];
  }
  return m;
}

// The hull of one primitive, which must have a thickness to have an oriented box.
void fit_hull(CompactFit& f, const Geometry& g, std::size_t prim) {
  f.h = ball_hull(g, prim);
  if (!(hull_max_radius(f.h) > 0.0))
    throw Error(std::string("obb: a ") + prim_type_name(g.type) + " of radius 0 has no oriented box");
}

// World axes: the object OBB's axes under the scene instance's map, made orthonormal and
// right-handed. For a similarity they are the mapped axes; under shear or a non-uniform
// scale the compact form (a rotation) holds a box fitted along them. (One fit; a block of
// segments takes fit_axes_lanes's lanes, the same operations.)
void fit_axes(CompactFit& f, const Geometry& g, const Affine3& xf) {
  f.axes = primitive_obb_axes(g, f.h);
  f.a0 = glm::normalize(xf.linear * f.axes[0]);
}

// The file's comment, 2 and 4: each try rounds the scale down and t to fp32, and checks
// the row in double.
bool fit_scale(CompactFit& f, int i, const Affine3& xf) {
  const QuatMatrix& q = f.q;
  std::uint32_t b = bf16_down(1.0 / (f.half[i] * q.norm2));
  for (int attempt = 0; attempt < 40 && b != 0; ++attempt) {
    const double s = bf16_value(b);
    if (!(s * q.norm2 < double(FLT_MAX))) return false;
    // Row i of M: sigma_i times column i of N (exact in double).
    const glm::dvec3 row = s * q.n[i];
    const float t = float(-glm::dot(row, f.centre));
    const BallHull::Pair sp = world_support_pair(f.h, xf, row);
    const double ext = std::max(std::abs(sp.plus + double(t)), std::abs(-sp.minus + double(t)));
    const double mx = glm::dot(glm::abs(row), f.reach);
    const double excess = ext + kMasqDecodeRelError * mx + 1e-12 * (mx + std::abs(double(t)) + 1.0) - 1.0;
    if (!std::isfinite(excess)) return false;
    if (excess <= 0.0) {
      f.c.t[i] = t;
      f.sigma[std::size_t(i)] = b;
      return true;
    }
    // Shrink by the excess (growing geometrically: re-rounding t can err again), at
    // least one bfloat16 step.
    std::uint32_t nb = bf16_down(s / (1.0 + std::ldexp(excess, attempt)));
    b = nb != 0 && nb < b ? nb : bf16_down(s) - 0x10000u;
    if ((b >> 23 & 0xFFu) == 0) b = 0;
  }
  return false;
}

} // namespace masq::compact_fit
