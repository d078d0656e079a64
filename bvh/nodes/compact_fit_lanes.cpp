// The compact fit's stages four primitives at a time (compact_fit.h), a primitive a lane
// of one vector register.
#include "bvh/nodes/compact_fit.h"
#include "scenes/prim_table.h"
#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstdint>
#if defined(__AVX__)
#include <immintrin.h>
#endif

namespace masq::compact_fit {

namespace {

// Four fits side by side, a primitive a lane (GCC/Clang vector extensions: one AVX
// register of doubles). Each lane runs, operation by operation and in the same order,
// what the fit's scalar glm code ran before it (normalize, dot, cross, inverse,
// std::max, std::abs, llround). An IEEE operation rounds the same in a lane as alone, and
// the build does not contract into fma (-ffp-contract=off), so the entries keep that
// code's bits: the build probe's structure digests (bear and Ratboy, capsules and curves,
// thin and thick, and the bundle, all under identity instance maps) did not change, and
// tests/test_compact_instance.cpp's random maps still fit conservatively.
typedef double D4 __attribute__((vector_size(32)));
typedef std::int64_t L4 __attribute__((vector_size(32)));
typedef float F4 __attribute__((vector_size(16)));

D4 splat(double x) { return D4{x, x, x, x}; }
// The four lanes get(0..3), built in registers. Writing a vector held in memory lane by
// lane and then reading it whole stalled each read on the four narrow stores (perf: the
// first operations on such vectors were the fit's hottest instructions).
template <class Get> D4 lanes_of(Get get) { return D4{get(0), get(1), get(2), get(3)}; }
// Lane l's fit of a block of n: the spare lanes of a block of fewer than four repeat
// lane 0.
const CompactFit& lane_fit(CompactFit* const* f, int n, int l) { return *f[l < n ? l : 0]; }
D4 lane_max(D4 a, D4 b) { return a < b ? b : a; } // std::max(a, b), glm::max
D4 lane_min(D4 a, D4 b) { return b < a ? b : a; } // glm::min(a, b)
D4 lane_abs(D4 a) { return D4(L4(a) & L4{INT64_MAX, INT64_MAX, INT64_MAX, INT64_MAX}); } // std::abs
// std::sqrt and std::trunc lane by lane: one instruction each with AVX (correctly
// rounded and exact, as the scalar ones), else the scalar calls.
D4 lane_sqrt(D4 a) {
#if defined(__AVX__)
  return D4(_mm256_sqrt_pd(__m256d(a)));
#else
  for (int k = 0; k < 4; ++k) a[k] = std::sqrt(a[k]);
  return a;
#endif
}
D4 lane_trunc(D4 a) {
#if defined(__AVX__)
  return D4(_mm256_round_pd(__m256d(a), _MM_FROUND_TO_ZERO | _MM_FROUND_NO_EXC));
#else
  for (int k = 0; k < 4; ++k) a[k] = std::trunc(a[k]);
  return a;
#endif
}
// std::llround lane by lane for |x| < 2^52 (half away from zero: x - trunc(x) is exact),
// as doubles holding the integers; llround itself was a library call, four per entry.
D4 lane_round_half_away(D4 x) {
  D4 t = lane_trunc(x);
  const D4 sign = D4(L4(splat(1.0)) | (L4(x) & L4{INT64_MIN, INT64_MIN, INT64_MIN, INT64_MIN})); // copysign(1, x)
  return lane_abs(x - t) >= splat(0.5) ? t + sign : t;
}

// glm's dot and cross of two lane vectors ([component] -> four lanes), and its dmat3 *
// dvec3 with every lane under the same matrix: the same operations in the same order.
D4 lane_dot(const D4 a[3], const D4 b[3]) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
void lane_cross(const D4 a[3], const D4 b[3], D4 out[3]) {
  out[0] = a[1] * b[2] - b[1] * a[2];
  out[1] = a[2] * b[0] - b[2] * a[0];
  out[2] = a[0] * b[1] - b[0] * a[1];
}
void lane_times(const glm::dmat3& m, const D4 v[3], D4 out[3]) {
  for (int k = 0; k < 3; ++k) out[k] = splat(m[0][k]) * v[0] + splat(m[1][k]) * v[1] + splat(m[2][k]) * v[2];
}

struct LaneFits {
  D4 centre_of_ball[4][3]; // [ball][axis]
  D4 radius[4];
  int balls = 0;
  D4 n[3][3]; // QuatMatrix::n, [column][row]
  D4 norm2;
  D4 reach[3];
  D4 centre[3];
  D4 half[3];
};

// world_support_pair for the four lanes' hulls along the lanes' v.
void lane_support_pair(const LaneFits& lf, const Affine3& xf, const D4 v[3], D4& plus, D4& minus) {
  const glm::dmat3& m = xf.linear;
  D4 w[3];
  for (int k = 0; k < 3; ++k) w[k] = splat(m[k][0]) * v[0] + splat(m[k][1]) * v[1] + splat(m[k][2]) * v[2];
  const D4 len = lane_sqrt(lane_dot(w, w));
  plus = minus = splat(-INFINITY);
  for (int b = 0; b < lf.balls; ++b) {
    const D4 d = lane_dot(w, lf.centre_of_ball[b]);
    const D4 r = lf.radius[b] * len;
    plus = lane_max(plus, d + r);
    minus = lane_max(minus, -d + r);
  }
  const glm::dvec3& t = xf.translation;
  const D4 shift = v[0] * splat(t.x) + v[1] * splat(t.y) + v[2] * splat(t.z);
  plus = plus + shift;
  minus = minus - shift;
}

} // namespace

// The centre and half extents along the decoded axes (columns of N / |q|^2), then
// fit_scale's first try of every axis. A lane whose first try of an axis does not fit
// (0.2% of the bear's axes) runs that axis's fit_scale on its own.
void fit_extent_lanes(CompactFit* const* f, int n, const Affine3& xf) {
  LaneFits lf;
  for (int l = 0; l < n; ++l) lf.balls = std::max(lf.balls, f[l]->h.count);
  // A hull of fewer balls repeats its first: the support's max is the same number.
  for (int b = 0; b < lf.balls; ++b) {
    auto from = [&](int l) { return std::size_t(b < lane_fit(f, n, l).h.count ? b : 0); };
    for (int j = 0; j < 3; ++j)
      lf.centre_of_ball[b][j] = lanes_of([&](int l) { return lane_fit(f, n, l).h.centre[from(l)][j]; });
    lf.radius[b] = lanes_of([&](int l) { return lane_fit(f, n, l).h.radius[from(l)]; });
  }
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) lf.n[i][j] = lanes_of([&](int l) { return lane_fit(f, n, l).q.n[i][j]; });
  lf.norm2 = lanes_of([&](int l) { return lane_fit(f, n, l).q.norm2; });
  // hull_world_box's operations in lanes (the map's row lengths once for the block): each
  // ball's centre mapped, grown by its radius times the row lengths. A lane's repeated
  // first ball changes no bit of its box.
  const glm::dvec3 row_len = row_lengths(xf);
  D4 box_lo[3], box_hi[3]; // the hulls' world boxes
  for (int k = 0; k < 3; ++k) box_lo[k] = splat(INFINITY), box_hi[k] = splat(-INFINITY);
  for (int b = 0; b < lf.balls; ++b) {
    D4 c[3];
    lane_times(xf.linear, lf.centre_of_ball[b], c);
    for (int k = 0; k < 3; ++k) {
      c[k] = c[k] + splat(xf.translation[k]);
      const D4 r = lf.radius[b] * splat(row_len[k]);
      box_lo[k] = lane_min(box_lo[k], c[k] - r);
      box_hi[k] = lane_max(box_hi[k], c[k] + r);
    }
  }
  for (int k = 0; k < 3; ++k) lf.reach[k] = lane_max(lane_abs(box_lo[k]), lane_abs(box_hi[k])); // X_j
  for (int l = 0; l < n; ++l)
    for (int k = 0; k < 3; ++k) {
      f[l]->exact.lo[k] = box_lo[k][l], f[l]->exact.hi[k] = box_hi[k][l];
      f[l]->reach[k] = lf.reach[k][l];
    }
  for (int j = 0; j < 3; ++j) lf.centre[j] = splat(0.0);
  for (int i = 0; i < 3; ++i) {
    const D4 e[3] = {lf.n[i][0] / lf.norm2, lf.n[i][1] / lf.norm2, lf.n[i][2] / lf.norm2};
    D4 plus, minus;
    lane_support_pair(lf, xf, e, plus, minus);
    const D4 hi = plus, lo = -minus;
    const D4 mid = splat(0.5) * (hi + lo);
    for (int j = 0; j < 3; ++j) lf.centre[j] = lf.centre[j] + mid * e[j];
    lf.half[i] = splat(0.5) * (hi - lo);
  }
  for (int l = 0; l < n; ++l)
    for (int j = 0; j < 3; ++j) f[l]->centre[j] = lf.centre[j][l], f[l]->half[j] = lf.half[j][l];
  for (int i = 0; i < 3; ++i) {
    const D4 inv = splat(1.0) / (lf.half[i] * lf.norm2);
    std::uint32_t b[4];
    for (int l = 0; l < 4; ++l) b[l] = bf16_down(inv[l]);
    const D4 s = lanes_of([&](int l) { return bf16_value(b[l]); });
    const D4 row[3] = {s * lf.n[i][0], s * lf.n[i][1], s * lf.n[i][2]};
    const D4 dot = lane_dot(row, lf.centre);
    float t[4];
    for (int l = 0; l < 4; ++l) t[l] = float(-dot[l]);
    const D4 td = lanes_of([&](int l) { return double(t[l]); });
    D4 plus, minus;
    lane_support_pair(lf, xf, row, plus, minus);
    const D4 ext = lane_max(lane_abs(plus + td), lane_abs(-minus + td));
    const D4 mx = lane_abs(row[0]) * lf.reach[0] + lane_abs(row[1]) * lf.reach[1] + lane_abs(row[2]) * lf.reach[2];
    const D4 excess = ext + splat(kMasqDecodeRelError) * mx + splat(1e-12) * (mx + lane_abs(td) + splat(1.0)) - splat(1.0);
    const D4 scaled = s * lf.norm2;
    for (int l = 0; l < n; ++l) {
      CompactFit& a = *f[l];
      if (b[l] != 0 && scaled[l] < double(FLT_MAX) && std::isfinite(excess[l]) && excess[l] <= 0.0) {
        a.c.t[i] = t[l];
        a.sigma[std::size_t(i)] = b[l];
      } else if (a.live) {
        a.live = fit_scale(a, i, xf);
      }
    }
  }
}

// primitive_obb_axes and the first world axis of a block of segments (two balls each),
// lane by lane the scalar code's operations (main_axis, perpendicular, glm's cross,
// normalize and matrix product): a chain of square roots and divisions per primitive,
// which four lanes overlap. Other blocks (balls, curves, hulls of other sizes) take
// fit_axes one fit at a time.
void fit_axes_lanes(CompactFit* const* f, int n, const Geometry& g, const std::int32_t* prims, const Affine3& xf) {
  bool segments = scene_prim_row(g.type).shape == PrimShape::Segment;
  for (int l = 0; l < n; ++l) {
    fit_hull(*f[l], g, std::size_t(prims[l]));
    segments = segments && f[l]->h.count == 2;
  }
  if (!segments) {
    for (int l = 0; l < n; ++l) fit_axes(*f[l], g, xf);
    return;
  }
  D4 c0[3], c1[3];
  for (int k = 0; k < 3; ++k) {
    c0[k] = lanes_of([&](int l) { return lane_fit(f, n, l).h.centre[0][k]; });
    c1[k] = lanes_of([&](int l) { return lane_fit(f, n, l).h.centre[1][k]; });
  }
  // main_axis: the chord over its length where that is positive, else +z.
  const D4 d[3] = {c1[0] - c0[0], c1[1] - c0[1], c1[2] - c0[2]};
  const D4 len = lane_sqrt(lane_dot(d, d));
  const auto chord = len > splat(0.0);
  const D4 w[3] = {chord ? d[0] / len : splat(0.0), chord ? d[1] / len : splat(0.0), chord ? d[2] / len : splat(1.0)};
  // perpendicular: the cross product with x (or y, where |w.x| >= 0.6), normalised.
  const auto small_x = lane_abs(w[0]) < splat(0.6);
  const D4 helper[3] = {small_x ? splat(1.0) : splat(0.0), small_x ? splat(0.0) : splat(1.0), splat(0.0)};
  D4 u1[3], u2[3];
  lane_cross(w, helper, u1);
  const D4 inv_u1 = splat(1.0) / lane_sqrt(lane_dot(u1, u1));
  for (int k = 0; k < 3; ++k) u1[k] = u1[k] * inv_u1;
  lane_cross(w, u1, u2);
  // The first world axis: normalize(xf.linear * w).
  D4 a0[3];
  lane_times(xf.linear, w, a0);
  const D4 inv_a0 = splat(1.0) / lane_sqrt(lane_dot(a0, a0));
  for (int l = 0; l < n; ++l) {
    CompactFit& a = *f[l];
    for (int k = 0; k < 3; ++k) {
      a.axes[0][k] = w[k][l];
      a.axes[1][k] = u1[k][l];
      a.axes[2][k] = u2[k][l];
      a.a0[k] = a0[k][l] * inv_a0[l];
    }
  }
}

// The second world axis (Gram-Schmidt), the third (a cross product), then the rotation's
// quaternion (Shepperd: the case of each lane picked per lane), rounded to 16 bits.
void fit_rotation_lanes(CompactFit* const* f, int n, const Affine3& xf) {
  D4 a0[3], v[3];
  for (int j = 0; j < 3; ++j) {
    a0[j] = lanes_of([&](int l) { return lane_fit(f, n, l).a0[j]; });
    v[j] = lanes_of([&](int l) { return lane_fit(f, n, l).axes[1][j]; });
  }
  D4 a1[3];
  lane_times(xf.linear, v, a1);
  const D4 along = lane_dot(a1, a0);
  for (int k = 0; k < 3; ++k) a1[k] = a1[k] - along * a0[k];
  const D4 inv_len = splat(1.0) / lane_sqrt(lane_dot(a1, a1)); // glm::normalize
  for (int k = 0; k < 3; ++k) a1[k] = a1[k] * inv_len;
  D4 a2[3];
  lane_cross(a0, a1, a2);
  // quaternion_of(dmat3(a0, a1, a2)): r(row, col) is column col's row.
  const D4* col[3] = {a0, a1, a2};
  auto r = [&](int row, int c) { return col[c][row]; };
  const D4 tr = r(0, 0) + r(1, 1) + r(2, 2);
  const D4 arg[4] = {tr + splat(1.0), splat(1.0) + r(0, 0) - r(1, 1) - r(2, 2),
                     splat(1.0) + r(1, 1) - r(0, 0) - r(2, 2), splat(1.0) + r(2, 2) - r(0, 0) - r(1, 1)};
  const D4 d21 = r(2, 1) - r(1, 2), d02 = r(0, 2) - r(2, 0), d10 = r(1, 0) - r(0, 1);
  const D4 s01 = r(0, 1) + r(1, 0), s02 = r(0, 2) + r(2, 0), s12 = r(1, 2) + r(2, 1);
  // Per case the numerators of (x, y, z, w) over s, and which of them is 0.25 s instead.
  const D4* num[4][4] = {{&d21, &d02, &d10, &d21}, {&d21, &s01, &s02, &d21}, {&s01, &s01, &s12, &d02},
                         {&s02, &s12, &s12, &d10}};
  int kase[4];
  for (int l = 0; l < 4; ++l) {
    const bool diag0 = r(0, 0)[l] > r(1, 1)[l] && r(0, 0)[l] > r(2, 2)[l];
    kase[l] = tr[l] > 0.0 ? 0 : diag0 ? 1 : r(1, 1)[l] > r(2, 2)[l] ? 2 : 3;
  }
  const D4 pick_arg = lanes_of([&](int l) { return arg[kase[l]][l]; });
  auto numerator = [&](int k) { return lanes_of([&](int l) { return (*num[kase[l]][k])[l]; }); };
  const D4 s = splat(2.0) * lane_sqrt(pick_arg);
  const D4 quarter = splat(0.25) * s;
  // Component k of (w, x, y, z) is 0.25 s in the lanes of case k, its numerator over s
  // in the others.
  auto component = [&](int k, const D4& over_s) {
    return lanes_of([&](int l) { return kase[l] == k ? quarter[l] : over_s[l]; });
  };
  const D4 w = component(0, numerator(3) / s), x = component(1, numerator(0) / s), y = component(2, numerator(1) / s),
           z = component(3, numerator(2) / s);
  const D4 len = lane_sqrt(x * x + y * y + z * z + w * w);
  const D4 scale = splat(double(kQuatScale));
  const D4 qi[4] = {lane_round_half_away(x / len * scale), lane_round_half_away(y / len * scale),
                    lane_round_half_away(z / len * scale), lane_round_half_away(w / len * scale)};
  // quat_matrix in lanes: the components are integers of at most 2^15 in magnitude, so
  // every product and sum below is an integer under 2^53, exact in double: the values of
  // its int64 arithmetic, in its order.
  const D4 &x_i = qi[0], &y_i = qi[1], &z_i = qi[2], &w_i = qi[3];
  const D4 xx = x_i * x_i, yy = y_i * y_i, zz = z_i * z_i, ww = w_i * w_i;
  const D4 xy = x_i * y_i, xz = x_i * z_i, yz = y_i * z_i, wx = w_i * x_i, wy = w_i * y_i, wz = w_i * z_i;
  const D4 two = splat(2.0);
  const D4 rows[3][3] = {{ww + xx - yy - zz, two * (xy - wz), two * (xz + wy)},
                         {two * (xy + wz), ww - xx + yy - zz, two * (yz - wx)},
                         {two * (xz - wy), two * (yz + wx), ww - xx - yy + zz}};
  const D4 norm2 = xx + yy + zz + ww;
  for (int l = 0; l < n; ++l) {
    CompactFit& a = *f[l];
    if (!std::isfinite(a2[0][l]) || !std::isfinite(a2[1][l]) || !std::isfinite(a2[2][l])) {
      a.live = false;
      continue;
    }
    for (int k = 0; k < 4; ++k) a.qi[std::size_t(k)] = std::int64_t(qi[k][l]);
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) a.q.n[j][i] = rows[i][j][l]; // QuatMatrix::n[column][row]
    a.q.norm2 = norm2[l];
    // The kernel's int32 arithmetic needs |N_ij| <= |q|^2 < 2^31 (|q|^2 ~ 32767^2 here).
    if (!(a.q.norm2 > 0.0) || a.q.norm2 >= 2147483647.0) a.live = false;
  }
}

// complete_masquerade_box's operations (glm's inverse, the unit box's corners, the
// intersection with the exact box, the crosses of the OBB's area). The boxes are written
// in place: copies of them were a few percent of a build.
void complete_lanes(CompactFit* const* f, int n, MasqueradeBox* const* out, bool* ok) {
  // decode_with in lanes: M_ij = sigma_i N_ji (m[j][i], glm's column j), t as stored.
  D4 m[3][3], t[3];
  for (int i = 0; i < 3; ++i) {
    const D4 sigma = lanes_of([&](int l) { return decoded_scale(lane_fit(f, n, l).c, i); });
    for (int j = 0; j < 3; ++j) m[j][i] = sigma * lanes_of([&](int l) { return lane_fit(f, n, l).q.n[i][j]; });
    t[i] = lanes_of([&](int l) { return double(lane_fit(f, n, l).c.t[i]); });
  }
  // glm::inverse of a 3x3 matrix, then inverse()'s translation -(L^-1 t).
  const D4 one_over_det = splat(1.0) / (m[0][0] * (m[1][1] * m[2][2] - m[2][1] * m[1][2]) -
                                        m[1][0] * (m[0][1] * m[2][2] - m[2][1] * m[0][2]) +
                                        m[2][0] * (m[0][1] * m[1][2] - m[1][1] * m[0][2]));
  D4 u[3][3];
  u[0][0] = (m[1][1] * m[2][2] - m[2][1] * m[1][2]) * one_over_det;
  u[1][0] = -(m[1][0] * m[2][2] - m[2][0] * m[1][2]) * one_over_det;
  u[2][0] = (m[1][0] * m[2][1] - m[2][0] * m[1][1]) * one_over_det;
  u[0][1] = -(m[0][1] * m[2][2] - m[2][1] * m[0][2]) * one_over_det;
  u[1][1] = (m[0][0] * m[2][2] - m[2][0] * m[0][2]) * one_over_det;
  u[2][1] = -(m[0][0] * m[2][1] - m[2][0] * m[0][1]) * one_over_det;
  u[0][2] = (m[0][1] * m[1][2] - m[1][1] * m[0][2]) * one_over_det;
  u[1][2] = -(m[0][0] * m[1][2] - m[1][0] * m[0][2]) * one_over_det;
  u[2][2] = (m[0][0] * m[1][1] - m[1][0] * m[0][1]) * one_over_det;
  D4 ut[3];
  for (int k = 0; k < 3; ++k) ut[k] = -(u[0][k] * t[0] + u[1][k] * t[1] + u[2][k] * t[2]);
  // The unit box's corners in world space, grown as Aabb::grow grows (glm::min, max).
  D4 lo[3], hi[3];
  for (int k = 0; k < 3; ++k) lo[k] = splat(INFINITY), hi[k] = splat(-INFINITY);
  for (int i = 0; i < 8; ++i) {
    const D4 p[3] = {splat(i & 1 ? 1 : -1), splat(i & 2 ? 1 : -1), splat(i & 4 ? 1 : -1)};
    for (int k = 0; k < 3; ++k) {
      const D4 x = u[0][k] * p[0] + u[1][k] * p[1] + u[2][k] * p[2] + ut[k];
      lo[k] = x < lo[k] ? x : lo[k];
      hi[k] = hi[k] < x ? x : hi[k];
    }
  }
  // obb_area: 8 (|e0 x e1| + |e1 x e2| + |e2 x e0|), e_c the columns of the inverse.
  auto cross_length = [&](int a, int b) {
    D4 c[3];
    lane_cross(u[a], u[b], c);
    return lane_sqrt(lane_dot(c, c));
  };
  const D4 obb_area = splat(8.0) * (cross_length(0, 1) + cross_length(1, 2) + cross_length(2, 0));
  // to_mat3x4f of both maps in lanes (row r: column c's entries, then the translation's):
  // a vector conversion rounds each lane to nearest, as float(x) does.
  F4 w2u[12], u2w[12];
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) {
      w2u[4 * r + c] = __builtin_convertvector(m[c][r], F4);
      u2w[4 * r + c] = __builtin_convertvector(u[c][r], F4);
    }
    w2u[4 * r + 3] = __builtin_convertvector(t[r], F4);
    u2w[4 * r + 3] = __builtin_convertvector(ut[r], F4);
  }
  for (int l = 0; l < n; ++l) {
    const Aabb& exact = f[l]->exact;
    MasqueradeBox& box = *out[l];
    for (int k = 0; k < 12; ++k) {
      box.world_to_unit[std::size_t(k)] = w2u[k][l];
      box.unit_to_world[std::size_t(k)] = u2w[k][l];
    }
    Aabb corners;
    for (int k = 0; k < 3; ++k) corners.lo[k] = lo[k][l], corners.hi[k] = hi[k][l];
    box.world_box = Aabb::intersect(exact, corners);
    bool valid = true;
    for (int k = 0; k < 3; ++k)
      valid = valid && box.world_box.lo[k] <= box.world_box.hi[k] && std::isfinite(box.world_box.lo[k]) &&
              std::isfinite(box.world_box.hi[k]);
    ok[l] = valid;
    box.obb_area = obb_area[l];
    box.aabb_area = exact.area();
  }
}

} // namespace masq::compact_fit
