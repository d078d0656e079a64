// cpu dialect only: the robust capsule intersector (intersect_capsule.h) on up to four
// capsules of a BVH leaf at once, one capsule per lane, with the GCC/Clang vector
// extensions. Every lane performs the operations of intersect_capsule in the same
// order, branches becoming lane masks, so each lane's crossing is bit-identical to the
// scalar call with the same interval; traverse.h's intersect_leaf then takes the lanes
// in reference order exactly as the one-source loop does. Measured: docs/kernels.md.
#ifndef MASQ_KERNEL_CAPSULE_SIMD_CPP_H
#define MASQ_KERNEL_CAPSULE_SIMD_CPP_H
#if defined(MASQ_LANG_CPP)
#include "intersect_capsule.h"
#include "slab_simd_cpp.h"
#include <cmath>
#include <cstring>
#include <limits>

namespace masq::kernel::simd {

// Lane i: capsule i's nearest crossing in [its self window, tmax] (hit != 0), with the
// unnormalised normal and axial parameter intersect_capsule gives it.
template <int L> struct CapsuleHitsN {
  float t[L];
  int hit[L];
  float nx[L], ny[L], nz[L];
  float u[L];
};
using CapsuleHits4 = CapsuleHitsN<4>;

// IEEE square root per lane (correctly rounded, as std::sqrt).
inline F4 vsqrt(F4 x) {
#if defined(__SSE__)
  return __builtin_ia32_sqrtps(x);
#else
  F4 r;
  for (int i = 0; i < 4; ++i) r[i] = std::sqrt(x[i]);
  return r;
#endif
}
inline F8 vsqrt(F8 x) {
#if defined(__AVX__)
  return __builtin_ia32_sqrtps256(x);
#else
  F8 r;
  for (int i = 0; i < 8; ++i) r[i] = std::sqrt(x[i]);
  return r;
#endif
}

template <class F> inline F vdot(F ax, F ay, F az, F bx, F by, F bz) { return (ax * bx + ay * by) + az * bz; } // glm's order
template <class F> inline F splat_as(float x) { return x - F{}; }
inline F4 splat(float x) { return splat_as<F4>(x); }

// L capsules side by side (four or eight lanes), one vector per coordinate.
template <class F> struct CapsuleLanes {
  F ax, ay, az, bx, by, bz, r;
};

// The cpu's row copy of the leaf capsules (host/cpu/leaf_capsules.h): row k (ax, ay, az,
// bx, by, bz, radius) at rows + k * stride, slot i of a row the capsule reference i names.
// Four lanes from slot `first`: a leaf's block; the slots past the leaf hold whatever
// follows it (the next leaf, or the rows' zero padding) and are masked off.
inline CapsuleLanes<F4> capsule_rows4(const float* rows, int stride, int first) {
  const float* p = rows + first;
  return {load<F4>(p), load<F4>(p + stride), load<F4>(p + 2 * stride), load<F4>(p + 3 * stride),
          load<F4>(p + 4 * stride), load<F4>(p + 5 * stride), load<F4>(p + 6 * stride)};
}
// Eight lanes: four from slot first_a, four from slot first_b (two leaves' blocks).
inline F8 join(F4 lo, F4 hi) { return __builtin_shufflevector(lo, hi, 0, 1, 2, 3, 4, 5, 6, 7); }
inline CapsuleLanes<F8> capsule_rows8(const float* rows, int stride, int first_a, int first_b) {
  CapsuleLanes<F4> a = capsule_rows4(rows, stride, first_a), b = capsule_rows4(rows, stride, first_b);
  return {join(a.ax, b.ax), join(a.ay, b.ay), join(a.az, b.az), join(a.bx, b.bx),
          join(a.by, b.by), join(a.bz, b.bz), join(a.r, b.r)};
}

// Capsules c[0..n-1] of an array as four lanes (lanes n..3 repeat lane 0).
inline CapsuleLanes<F4> capsule_lanes4(const Capsule* c, int n) {
  CapsuleLanes<F4> l;
  for (int i = 0; i < 4; ++i) {
    const Capsule& k = c[i < n ? i : 0];
    l.ax[i] = k.a[0];
    l.ay[i] = k.a[1];
    l.az[i] = k.a[2];
    l.bx[i] = k.b[0];
    l.by[i] = k.b[1];
    l.bz[i] = k.b[2];
    l.r[i] = k.radius;
  }
  return l;
}

// The lanes' capsules against the ray (o, d) within [tmin, tmax]; lanes off in `valid`
// report no hit. Every lane count performs the same operations lane by lane.
template <class F, class I>
FN_INLINED CapsuleHitsN<int(sizeof(F) / 4)> capsule_hits(const CapsuleLanes<F>& c, I valid, glm::vec3 o, glm::vec3 d,
                                                          float tmin, float tmax) {
  constexpr int L = int(sizeof(F) / 4);
  CapsuleHitsN<L> out;
  const F ax = c.ax, ay = c.ay, az = c.az, bx = c.bx, by = c.by, bz = c.bz, r = c.r;
  auto splat = [](float x) { return splat_as<F>(x); };
  float dd = glm::dot(d, d);
  I ok = valid & (r > 0.0f);
  if (!(dd > 0.0f) || !(tmin <= tmax)) ok = I{};
  F bax = bx - ax, bay = by - ay, baz = bz - az;
  F L2 = vdot(bax, bay, baz, bax, bay, baz);
  F len = vsqrt(L2);
  float dl = std::sqrt(dd);
  F h = 0.5f * len;
  F ocx = (o.x - ax) - 0.5f * bax, ocy = (o.y - ay) - 0.5f * bay, ocz = (o.z - az) - 0.5f * baz;
  F ts = -vdot(ocx, ocy, ocz, splat(d.x), splat(d.y), splat(d.z)) / dd;
  F px = ocx + ts * d.x, py = ocy + ts * d.y, pz = ocz + ts * d.z;
  // Most leaves are crossed without a hit, so two conservative tests come first; when
  // they clear every lane, every scalar call misses too and the rest is skipped.
  // Otherwise all lanes run in full, so the lanes stay bit-identical to the scalar calls.
  // Sphere: every crossing lies within h + r of the centre, and p is the line's closest
  // point to it up to the rounding of ts and p (bounded by the 64u term): a line that
  // passes farther, even with 1% to spare, misses.
  float d1 = std::fabs(d.x) + std::fabs(d.y) + std::fabs(d.z);
  F oc1 = (vabs(ocx) + vabs(ocy)) + vabs(ocz);
  F rounding = 64.0f * MASQ_U * (oc1 + vabs(ts) * d1);
  F reach = (h + r) * 1.01f + rounding;
  I near = ok & (vdot(px, py, pz, px, py, pz) <= reach * reach);
  // Axis line: every crossing also lies within r of the capsule's axis line, so within r
  // of it along n = d x (b - a), the normal of both lines: |oc.n| <= r |n|. With the
  // scalar call's own rounding in R (as in the sphere's reach, plus the axis length), and
  // K bounding the rest: the rounding of n (|e| <= 6u |d| len, which tilts n off both
  // lines by up to |e| over the crossing's distances from o and the centre, at most
  // |oc| + len + R), of oc (2u (|oc| + 2 len)) and of the dot product (3u |oc| |n|), all
  // within 64u |d| len (|oc|_1 + len + R). A ray along the axis (n about 0) never passes
  // this test's miss, nor a zero-length capsule (n = 0), nor any NaN.
  F lnx = d.y * baz - d.z * bay, lny = d.z * bax - d.x * baz, lnz = d.x * bay - d.y * bax;
  F R = r * 1.01f + rounding + 64.0f * MASQ_U * len;
  F K = (64.0f * MASQ_U * dl) * len * (oc1 + len + R);
  F gap = vabs(vdot(ocx, ocy, ocz, lnx, lny, lnz)) - K;
  I off_axis = (gap > 0.0f) & (gap * gap > (R * R) * vdot(lnx, lny, lnz, lnx, lny, lnz) * 1.01f);
  near = near & ~off_axis;
  auto any_lane = [](I lanes) {
    int any = 0;
    for (int i = 0; i < L; ++i) any |= lanes[i];
    return any != 0;
  };
  auto no_hits = [&out]() {
    for (int i = 0; i < L; ++i) out.hit[i] = 0;
    return out;
  };
  if (!any_lane(near)) return no_hits();
  // Behind the start: a secondary ray leaves a strand through the capsules it starts on
  // or behind (its neighbours'), whose crossings all lie before its interval opens: a
  // third of the eight-lane calls that got this far on the bear's diffuse rays, and a
  // sixth on its shadow rays. If the ray at tmin is outside R of the axis line (the
  // crossings' bound above) and moving away from it, its distance to the axis only grows
  // from there (a convex quadratic in t, rising at tmin), so the scalar call finds no
  // crossing in its window, which starts at or after tmin. E bounds the error of the
  // point q at tmin (its own rounding, oc's, and the axis direction's over |q|); the 64u
  // and 32u terms the rounding of the products and dot products below, the cancellation
  // in A - B included. Only where some near lane's sphere reaches back to tmin (ts - tmin
  // at most reach / |d|): a capsule wholly ahead of the start, as every capsule a camera
  // ray meets, is left to the full test without this test's cost.
  I starts_in_reach = near & ((ts - tmin) * dl <= reach);
  if (any_lane(starts_in_reach)) {
    F qx = ocx + tmin * d.x, qy = ocy + tmin * d.y, qz = ocz + tmin * d.z;
    F q1 = (vabs(qx) + vabs(qy)) + vabs(qz);
    F ba1 = (vabs(bax) + vabs(bay)) + vabs(baz);
    F E = 8.0f * MASQ_U * (oc1 + len + std::fabs(tmin) * d1 + q1);
    F qb = vdot(qx, qy, qz, bax, bay, baz);
    // A - B = (q's distance to the axis line)^2 |b - a|^2
    F A = vdot(qx, qy, qz, qx, qy, qz) * L2, B = qb * qb;
    F RE = R + E;
    I outside = (A - B) - 64.0f * MASQ_U * (A + B) > RE * RE * L2;
    // half that squared distance's derivative in t at tmin, times |b - a|^2
    F db = vdot(splat(d.x), splat(d.y), splat(d.z), bax, bay, baz);
    F slope = vdot(qx, qy, qz, splat(d.x), splat(d.y), splat(d.z)) * L2 - qb * db;
    I away = slope > (32.0f * MASQ_U * q1 + 2.0f * E) * d1 * (L2 + ba1 * ba1);
    near = near & ~(outside & away);
  }
  if (!any_lane(near)) return no_hits();
  I long_axis = len > 0.0f;
  F wx = long_axis ? bax / len : splat(0.0f);
  F wy = long_axis ? bay / len : splat(0.0f);
  F wz = long_axis ? baz / len : splat(1.0f);
  F self = (MASQ_SELF_REL * r + 32.0f * MASQ_U * (vsqrt(vdot(ocx, ocy, ocz, ocx, ocy, ocz)) + len)) / dl;
  F tlo = vmax(splat(tmin), self);
  // From here every lane performs intersect_capsule's operations in its order.
  F oax = o.x - ax, oay = o.y - ay, oaz = o.z - az;
  F obx = o.x - bx, oby = o.y - by, obz = o.z - bz;
  F ta = -vdot(oax, oay, oaz, splat(d.x), splat(d.y), splat(d.z)) / dd;
  F tb = -vdot(obx, oby, obz, splat(d.x), splat(d.y), splat(d.z)) / dd;
  F pax = oax + ta * d.x, pay = oay + ta * d.y, paz = oaz + ta * d.z;
  F pbx = obx + tb * d.x, pby = oby + tb * d.y, pbz = obz + tb * d.z;
  F da = vdot(splat(d.x), splat(d.y), splat(d.z), wx, wy, wz);
  const F inf = splat(std::numeric_limits<float>::infinity());
  F t_in = inf, t_out = -inf, s_in = splat(0.0f), s_out = splat(0.0f);
  I e_in = I{}, e_out = I{};
  // Balls, each in its endpoint's frame.
  for (int e = 0; e < 2; ++e) {
    F pcx = e == 0 ? pax : pbx, pcy = e == 0 ? pay : pby, pcz = e == 0 ? paz : pbz;
    F tc = e == 0 ? ta : tb;
    F c0 = -vdot(pcx, pcy, pcz, splat(d.x), splat(d.y), splat(d.z)) / dd;
    F ux = pcx + c0 * d.x, uy = pcy + c0 * d.y, uz = pcz + c0 * d.z;
    F lc = vsqrt(vdot(ux, uy, uz, ux, uy, uz));
    F dc = (r - lc) * (r + lc);
    I cap_ok = dc >= 0.0f;
    F qc = vsqrt(dc / dd);
    F t0 = tc + (c0 - qc), t1 = tc + (c0 + qc);
    I new_in = cap_ok & (t0 < t_in), new_out = cap_ok & (t1 > t_out);
    t_in = new_in ? t0 : t_in;
    s_in = new_in ? c0 - qc : s_in;
    e_in = new_in ? I{} + e : e_in;
    t_out = new_out ? t1 : t_out;
    s_out = new_out ? c0 + qc : s_out;
    e_out = new_out ? I{} + e : e_out;
  }
  // The finite cylinder in the axis frame of the nearer endpoint.
  I near_b = vdot(pbx, pby, pbz, pbx, pby, pbz) < vdot(pax, pay, paz, pax, pay, paz);
  I nb = near_b ? I{} + 1 : I{};
  F pnx = near_b ? pbx : pax, pny = near_b ? pby : pay, pnz = near_b ? pbz : paz;
  F tn = near_b ? tb : ta;
  F pzz = vdot(pnx, pny, pnz, wx, wy, wz);
  F prx = pnx - pzz * wx, pry = pny - pzz * wy, prz = pnz - pzz * wz;
  F drx = d.x - da * wx, dry = d.y - da * wy, drz = d.z - da * wz;
  F drdr = vdot(drx, dry, drz, drx, dry, drz);
  F s0 = -vdot(prx, pry, prz, drx, dry, drz) / drdr;
  F vx = prx + s0 * drx, vy = pry + s0 * dry, vz = prz + s0 * drz;
  F lv = vsqrt(vdot(vx, vy, vz, vx, vy, vz));
  F disc = (r - lv) * (r + lv);
  I side_ok = (h > 0.0f) & (drdr > 0.0f) & (disc >= 0.0f);
  F q = vsqrt(disc / drdr);
  F lo = s0 - q, hi = s0 + q;
  F zlo = near_b ? -len : splat(0.0f), zhi = near_b ? splat(0.0f) : len;
  F sa = (zlo - pzz) / da, sb = (zhi - pzz) / da;
  I tilted = da != 0.0f;
  lo = tilted ? vmax(lo, vmin(sa, sb)) : lo;
  hi = tilted ? vmin(hi, vmax(sa, sb)) : hi;
  lo = (tilted | ((pzz >= zlo) & (pzz <= zhi))) ? lo : inf;
  side_ok = side_ok & (lo <= hi);
  I new_in = side_ok & (tn + lo < t_in), new_out = side_ok & (tn + hi > t_out);
  t_in = new_in ? tn + lo : t_in;
  s_in = new_in ? lo : s_in;
  e_in = new_in ? nb : e_in;
  t_out = new_out ? tn + hi : t_out;
  s_out = new_out ? hi : s_out;
  e_out = new_out ? nb : e_out;
  // The entry, or (from inside) the exit, within the window.
  I take_in = (t_in >= tlo) & (t_in <= tmax);
  I hit = ok & (t_in <= t_out) & (take_in | ((t_out >= tlo) & (t_out <= tmax)));
  I e = take_in ? e_in : e_out;
  I eb = e != 0;
  F sh = take_in ? s_in : s_out;
  F xx = (eb ? pbx : pax) + sh * d.x, xy = (eb ? pby : pay) + sh * d.y, xz = (eb ? pbz : paz) + sh * d.z;
  F z = vdot(xx, xy, xz, wx, wy, wz);
  F zn = eb ? z : -z;
  F nx = xx - z * wx, ny = xy - z * wy, nz = xz - z * wz;
  F u = eb ? 1.0f + z / len : z / len;
  I this_end = (zn >= 0.0f) | (h == 0.0f);
  I other_end = ~this_end & (zn <= -len);
  nx = this_end ? xx : (other_end ? (eb ? xx + bax : xx - bax) : nx);
  ny = this_end ? xy : (other_end ? (eb ? xy + bay : xy - bay) : ny);
  nz = this_end ? xz : (other_end ? (eb ? xz + baz : xz - baz) : nz);
  u = this_end ? (eb ? splat(1.0f) : splat(0.0f)) : (other_end ? (eb ? splat(0.0f) : splat(1.0f)) : u);
  u = vmin(vmax(u, splat(0.0f)), splat(1.0f));
  F t = take_in ? t_in : t_out;
  std::memcpy(out.t, &t, sizeof out.t);
  std::memcpy(out.hit, &hit, sizeof out.hit);
  std::memcpy(out.nx, &nx, sizeof out.nx);
  std::memcpy(out.ny, &ny, sizeof out.ny);
  std::memcpy(out.nz, &nz, sizeof out.nz);
  std::memcpy(out.u, &u, sizeof out.u);
  return out;
}

// The first n (1..4) lanes valid.
inline I4 lanes_below(int n) { return I4{0, 1, 2, 3} < n; }
// Capsules c[0..n-1] (n in 1..4) of an array against the ray (tests).
inline CapsuleHits4 capsule_hits4(const Capsule* c, int n, glm::vec3 o, glm::vec3 d, float tmin, float tmax) {
  return capsule_hits<F4, I4>(capsule_lanes4(c, n), lanes_below(n), o, d, tmin, tmax);
}

} // namespace masq::kernel::simd
#endif
#endif
