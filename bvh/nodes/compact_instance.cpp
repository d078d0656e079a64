// Encoder of compact masquerade entries. Why the stored map is conservative:
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
#include "bvh/nodes/compact_instance.h"
#include "bvh/bounds/prim_bounds.h"
#include "masq/error.h"
#include <algorithm>
#include <array>
#include <bit>
#include <cfloat>
#include <cmath>

namespace masq {

namespace {

constexpr std::int64_t kQuatScale = 32767;

// The largest bfloat16 <= x (bits of its fp32), or 0 when that is not a positive normal
// number (x too small or too large for the form).
std::uint32_t bf16_down(double x) {
  if (!(x > 0.0) || !std::isfinite(x)) return 0;
  float f = float(x);
  if (double(f) > x) f = std::nextafter(f, 0.0f);
  std::uint32_t b = std::bit_cast<std::uint32_t>(f) & 0xFFFF0000u;
  std::uint32_t e = (b >> 23) & 0xFFu;
  return (e == 0 || e == 255) ? 0 : b;
}

double bf16_value(std::uint32_t bits) { return double(std::bit_cast<float>(bits)); }

// A unit quaternion (x, y, z, w) of the rotation whose columns are the axes (Shepperd).
std::array<double, 4> quaternion_of(const glm::dmat3& a) {
  auto r = [&](int row, int col) { return a[col][row]; };
  double x, y, z, w;
  double tr = r(0, 0) + r(1, 1) + r(2, 2);
  if (tr > 0.0) {
    double s = 2.0 * std::sqrt(tr + 1.0);
    w = 0.25 * s, x = (r(2, 1) - r(1, 2)) / s, y = (r(0, 2) - r(2, 0)) / s, z = (r(1, 0) - r(0, 1)) / s;
  } else if (r(0, 0) > r(1, 1) && r(0, 0) > r(2, 2)) {
    double s = 2.0 * std::sqrt(1.0 + r(0, 0) - r(1, 1) - r(2, 2));
    w = (r(2, 1) - r(1, 2)) / s, x = 0.25 * s, y = (r(0, 1) + r(1, 0)) / s, z = (r(0, 2) + r(2, 0)) / s;
  } else if (r(1, 1) > r(2, 2)) {
    double s = 2.0 * std::sqrt(1.0 + r(1, 1) - r(0, 0) - r(2, 2));
    w = (r(0, 2) - r(2, 0)) / s, x = (r(0, 1) + r(1, 0)) / s, y = 0.25 * s, z = (r(1, 2) + r(2, 1)) / s;
  } else {
    double s = 2.0 * std::sqrt(1.0 + r(2, 2) - r(0, 0) - r(1, 1));
    w = (r(1, 0) - r(0, 1)) / s, x = (r(0, 2) + r(2, 0)) / s, y = (r(1, 2) + r(2, 1)) / s, z = 0.25 * s;
  }
  double l = std::sqrt(x * x + y * y + z * z + w * w);
  return {x / l, y / l, z / l, w / l};
}

std::int32_t half_i16(std::uint32_t word, int hi) {
  std::int32_t v = std::int32_t(hi ? word >> 16 : word & 0xFFFFu);
  return v >= 32768 ? v - 65536 : v;
}

std::uint32_t pack_i16(std::int64_t lo, std::int64_t hi) {
  return (std::uint32_t(lo) & 0xFFFFu) | ((std::uint32_t(hi) & 0xFFFFu) << 16);
}

// N = |q|^2 R(q), exactly (as the kernel's integer arithmetic): n[col][row], glm order.
struct QuatMatrix {
  glm::dmat3 n{0.0};
  double norm2 = 0; // |q|^2
};

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

// The hull's support in world space: h(L^T v) + v . T (exact for its balls' ellipsoids).
double world_support(const BallHull& h, const Affine3& xf, const glm::dvec3& v) {
  return h.support(glm::transpose(xf.linear) * v) + glm::dot(v, xf.translation);
}

} // namespace

Affine3 decode_masq_instance(const kernel::MasqInstance& c) {
  QuatMatrix q = quat_matrix(half_i16(c.q01, 0), half_i16(c.q01, 1), half_i16(c.q23, 0), half_i16(c.q23, 1));
  const double sigma[3] = {bf16_value(c.s01 << 16), bf16_value(c.s01 & 0xFFFF0000u),
                           bf16_value(c.s2_owner & 0xFFFF0000u)};
  Affine3 m;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) m.linear[j][i] = sigma[i] * q.n[i][j]; // M_ij = sigma_i N_ji
    m.translation[i] = c.t[i];
  }
  return m;
}

void set_masq_owner(kernel::MasqInstance& c, std::uint32_t owner) {
  if (owner >= std::uint32_t(MASQ_MAX_OWNERS)) throw Error("compact masquerade: owner index over 16 bits");
  c.s2_owner = (c.s2_owner & 0xFFFF0000u) | owner;
}

std::uint32_t masq_owner(const kernel::MasqInstance& c) { return c.s2_owner & MASQ_OWNER_MASK; }

std::optional<CompactMasquerade> compact_masquerade(const Geometry& g, std::size_t prim, const Affine3& xf) {
  BallHull h = ball_hull(g, prim);
  if (!(hull_max_radius(h) > 0.0))
    throw Error(std::string("obb: a ") + prim_type_name(g.type) + " of radius 0 has no oriented box");
  // World axes: the object OBB's axes under the scene instance's map, made orthonormal
  // and right-handed. For a similarity they are the mapped axes; under shear or a
  // non-uniform scale the compact form (a rotation) holds a box fitted along them.
  const glm::dmat3 axes = primitive_obb_axes(g, h);
  glm::dvec3 a0 = glm::normalize(xf.linear * axes[0]);
  glm::dvec3 a1 = xf.linear * axes[1];
  a1 = glm::normalize(a1 - glm::dot(a1, a0) * a0);
  glm::dvec3 a2 = glm::cross(a0, a1);
  if (!std::isfinite(a2.x) || !std::isfinite(a2.y) || !std::isfinite(a2.z)) return std::nullopt;
  std::array<double, 4> qd = quaternion_of(glm::dmat3(a0, a1, a2));
  std::array<std::int64_t, 4> qi{};
  for (int k = 0; k < 4; ++k) qi[std::size_t(k)] = std::llround(qd[std::size_t(k)] * double(kQuatScale));
  QuatMatrix q = quat_matrix(qi[0], qi[1], qi[2], qi[3]);
  // The kernel's int32 arithmetic needs |N_ij| <= |q|^2 < 2^31 (|q|^2 ~ 32767^2 here).
  if (!(q.norm2 > 0.0) || q.norm2 >= 2147483647.0) return std::nullopt;

  // Fit along the decoded axes (columns of N / |q|^2).
  const Aabb exact = hull_world_box(h, xf);
  const glm::dvec3 reach = glm::max(glm::abs(exact.lo), glm::abs(exact.hi)); // X_j
  glm::dvec3 centre(0.0), half(0.0);
  for (int i = 0; i < 3; ++i) {
    glm::dvec3 e = q.n[i] / q.norm2;
    double hi = world_support(h, xf, e), lo = -world_support(h, xf, -e);
    centre += 0.5 * (hi + lo) * e;
    half[i] = 0.5 * (hi - lo);
  }

  kernel::MasqInstance c{};
  c.prim = std::int32_t(prim);
  c.q01 = pack_i16(qi[0], qi[1]);
  c.q23 = pack_i16(qi[2], qi[3]);
  std::array<std::uint32_t, 3> sigma{};
  for (int i = 0; i < 3; ++i) {
    std::uint32_t b = bf16_down(1.0 / (half[i] * q.norm2));
    bool fits = false;
    for (int attempt = 0; attempt < 40 && b != 0; ++attempt) {
      const double s = bf16_value(b);
      if (!(s * q.norm2 < double(FLT_MAX))) return std::nullopt;
      // Row i of M: sigma_i times column i of N (exact in double).
      const glm::dvec3 row = s * q.n[i];
      const float t = float(-glm::dot(row, centre));
      const double ext = std::max(std::abs(world_support(h, xf, row) + double(t)),
                                  std::abs(-world_support(h, xf, -row) + double(t)));
      const double mx = glm::dot(glm::abs(row), reach);
      const double excess = ext + kMasqDecodeRelError * mx + 1e-12 * (mx + std::abs(double(t)) + 1.0) - 1.0;
      if (!std::isfinite(excess)) return std::nullopt;
      if (excess <= 0.0) {
        c.t[i] = t;
        fits = true;
        break;
      }
      // Shrink by the excess (growing geometrically: re-rounding t can err again), at
      // least one bfloat16 step.
      std::uint32_t nb = bf16_down(s / (1.0 + std::ldexp(excess, attempt)));
      b = nb != 0 && nb < b ? nb : bf16_down(s) - 0x10000u;
      if ((b >> 23 & 0xFFu) == 0) b = 0;
    }
    if (!fits) return std::nullopt;
    sigma[std::size_t(i)] = b;
  }
  c.s01 = (sigma[0] >> 16) | (sigma[1] & 0xFFFF0000u);
  c.s2_owner = sigma[2] & 0xFFFF0000u;

  std::optional<MasqueradeBox> box = complete_masquerade_box(decode_masq_instance(c), exact);
  if (!box) return std::nullopt;
  return CompactMasquerade{c, *box};
}

kernel::Instance tlas_entry_instance(const PackedScene& s, std::size_t entry) {
  if (entry < s.instances.size()) return s.instances[entry];
  if (entry - s.instances.size() >= s.masq_instances.size())
    throw Error("scene: TLAS entry " + std::to_string(entry) + " of " + std::to_string(s.tlas_entry_count()));
  const kernel::MasqInstance& c = s.masq_instances[entry - s.instances.size()];
  const std::size_t owner = masq_owner(c);
  if (owner >= s.masq_owners.size())
    throw Error("scene: compact masquerade entry " + std::to_string(entry - s.instances.size()) + " names owner " +
                std::to_string(owner) + " of " + std::to_string(s.masq_owners.size()));
  kernel::Instance k{};
  Mat3x4f m = to_mat3x4f(decode_masq_instance(c));
  std::copy(m.begin(), m.end(), k.world_to_object);
  k.blas_root = -1;
  k.geom = s.masq_owners[owner].geom;
  k.prim = c.prim;
  k.scene_inst = s.masq_owners[owner].scene_inst;
  return k;
}

} // namespace masq
