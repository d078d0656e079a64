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
struct CapsuleHits4 {
  float t[4];
  int hit[4];
  float nx[4], ny[4], nz[4];
  float u[4];
};

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

inline F4 vdot(F4 ax, F4 ay, F4 az, F4 bx, F4 by, F4 bz) { return (ax * bx + ay * by) + az * bz; } // glm's order
inline F4 splat(float x) { return x - F4{}; }

// Capsules c[0..n-1] (n in 1..4) against the ray (o, d) within [tmin, tmax].
FN_INLINED CapsuleHits4 capsule_hits4(const Capsule* c, int n, glm::vec3 o, glm::vec3 d, float tmin, float tmax) {
  CapsuleHits4 out;
  F4 ax, ay, az, bx, by, bz, r;
  for (int i = 0; i < 4; ++i) {
    const Capsule& k = c[i < n ? i : 0]; // idle lanes repeat lane 0 and are masked off
    ax[i] = k.a[0];
    ay[i] = k.a[1];
    az[i] = k.a[2];
    bx[i] = k.b[0];
    by[i] = k.b[1];
    bz[i] = k.b[2];
    r[i] = k.radius;
  }
  float dd = glm::dot(d, d);
  I4 ok = (I4{0, 1, 2, 3} < n) & (r > 0.0f);
  if (!(dd > 0.0f) || !(tmin <= tmax)) ok = I4{};
  F4 bax = bx - ax, bay = by - ay, baz = bz - az;
  F4 len = vsqrt(vdot(bax, bay, baz, bax, bay, baz));
  F4 h = 0.5f * len;
  F4 ocx = (o.x - ax) - 0.5f * bax, ocy = (o.y - ay) - 0.5f * bay, ocz = (o.z - az) - 0.5f * baz;
  F4 ts = -vdot(ocx, ocy, ocz, splat(d.x), splat(d.y), splat(d.z)) / dd;
  F4 px = ocx + ts * d.x, py = ocy + ts * d.y, pz = ocz + ts * d.z;
  // Most leaves are crossed without a hit, so two conservative tests come first; when
  // they clear every lane, every scalar call misses too and the rest is skipped.
  // Otherwise all lanes run in full, so the lanes stay bit-identical to the scalar calls.
  // Sphere: every crossing lies within h + r of the centre, and p is the line's closest
  // point to it up to the rounding of ts and p (bounded by the 64u term): a line that
  // passes farther, even with 1% to spare, misses.
  float d1 = std::fabs(d.x) + std::fabs(d.y) + std::fabs(d.z);
  F4 oc1 = (vabs(ocx) + vabs(ocy)) + vabs(ocz);
  F4 rounding = 64.0f * MASQ_U * (oc1 + vabs(ts) * d1);
  F4 reach = (h + r) * 1.01f + rounding;
  I4 near = ok & (vdot(px, py, pz, px, py, pz) <= reach * reach);
  // Axis line: every crossing also lies within r of the capsule's axis line, so within r
  // of it along n = d x (b - a), the normal of both lines: |oc.n| <= r |n|. With the
  // scalar call's own rounding in R (as in the sphere's reach, plus the axis length), and
  // K bounding the rest: the rounding of n (|e| <= 6u |d| len, which tilts n off both
  // lines by up to |e| over the crossing's distances from o and the centre, at most
  // |oc| + len + R), of oc (2u (|oc| + 2 len)) and of the dot product (3u |oc| |n|), all
  // within 64u |d| len (|oc|_1 + len + R). A ray along the axis (n about 0) never passes
  // this test's miss, nor a zero-length capsule (n = 0), nor any NaN.
  F4 lnx = d.y * baz - d.z * bay, lny = d.z * bax - d.x * baz, lnz = d.x * bay - d.y * bax;
  F4 R = r * 1.01f + rounding + 64.0f * MASQ_U * len;
  F4 K = (64.0f * MASQ_U * std::sqrt(dd)) * len * (oc1 + len + R);
  F4 gap = vabs(vdot(ocx, ocy, ocz, lnx, lny, lnz)) - K;
  I4 off_axis = (gap > 0.0f) & (gap * gap > (R * R) * vdot(lnx, lny, lnz, lnx, lny, lnz) * 1.01f);
  near = near & ~off_axis;
  if ((near[0] | near[1] | near[2] | near[3]) == 0) {
    for (int i = 0; i < 4; ++i) out.hit[i] = 0;
    return out;
  }
  I4 long_axis = len > 0.0f;
  F4 wx = long_axis ? bax / len : splat(0.0f);
  F4 wy = long_axis ? bay / len : splat(0.0f);
  F4 wz = long_axis ? baz / len : splat(1.0f);
  F4 self = (MASQ_SELF_REL * r + 32.0f * MASQ_U * (vsqrt(vdot(ocx, ocy, ocz, ocx, ocy, ocz)) + len)) / std::sqrt(dd);
  F4 tlo = vmax(splat(tmin), self);
  // From here every lane performs intersect_capsule's operations in its order.
  F4 oax = o.x - ax, oay = o.y - ay, oaz = o.z - az;
  F4 obx = o.x - bx, oby = o.y - by, obz = o.z - bz;
  F4 ta = -vdot(oax, oay, oaz, splat(d.x), splat(d.y), splat(d.z)) / dd;
  F4 tb = -vdot(obx, oby, obz, splat(d.x), splat(d.y), splat(d.z)) / dd;
  F4 pax = oax + ta * d.x, pay = oay + ta * d.y, paz = oaz + ta * d.z;
  F4 pbx = obx + tb * d.x, pby = oby + tb * d.y, pbz = obz + tb * d.z;
  F4 da = vdot(splat(d.x), splat(d.y), splat(d.z), wx, wy, wz);
  const F4 inf = splat(std::numeric_limits<float>::infinity());
  F4 t_in = inf, t_out = -inf, s_in = splat(0.0f), s_out = splat(0.0f);
  I4 e_in = I4{}, e_out = I4{};
  // Balls, each in its endpoint's frame.
  for (int e = 0; e < 2; ++e) {
    F4 pcx = e == 0 ? pax : pbx, pcy = e == 0 ? pay : pby, pcz = e == 0 ? paz : pbz;
    F4 tc = e == 0 ? ta : tb;
    F4 c0 = -vdot(pcx, pcy, pcz, splat(d.x), splat(d.y), splat(d.z)) / dd;
    F4 ux = pcx + c0 * d.x, uy = pcy + c0 * d.y, uz = pcz + c0 * d.z;
    F4 lc = vsqrt(vdot(ux, uy, uz, ux, uy, uz));
    F4 dc = (r - lc) * (r + lc);
    I4 cap_ok = dc >= 0.0f;
    F4 qc = vsqrt(dc / dd);
    F4 t0 = tc + (c0 - qc), t1 = tc + (c0 + qc);
    I4 new_in = cap_ok & (t0 < t_in), new_out = cap_ok & (t1 > t_out);
    t_in = new_in ? t0 : t_in;
    s_in = new_in ? c0 - qc : s_in;
    e_in = new_in ? I4{} + e : e_in;
    t_out = new_out ? t1 : t_out;
    s_out = new_out ? c0 + qc : s_out;
    e_out = new_out ? I4{} + e : e_out;
  }
  // The finite cylinder in the axis frame of the nearer endpoint.
  I4 near_b = vdot(pbx, pby, pbz, pbx, pby, pbz) < vdot(pax, pay, paz, pax, pay, paz);
  I4 nb = near_b ? I4{} + 1 : I4{};
  F4 pnx = near_b ? pbx : pax, pny = near_b ? pby : pay, pnz = near_b ? pbz : paz;
  F4 tn = near_b ? tb : ta;
  F4 pzz = vdot(pnx, pny, pnz, wx, wy, wz);
  F4 prx = pnx - pzz * wx, pry = pny - pzz * wy, prz = pnz - pzz * wz;
  F4 drx = d.x - da * wx, dry = d.y - da * wy, drz = d.z - da * wz;
  F4 drdr = vdot(drx, dry, drz, drx, dry, drz);
  F4 s0 = -vdot(prx, pry, prz, drx, dry, drz) / drdr;
  F4 vx = prx + s0 * drx, vy = pry + s0 * dry, vz = prz + s0 * drz;
  F4 lv = vsqrt(vdot(vx, vy, vz, vx, vy, vz));
  F4 disc = (r - lv) * (r + lv);
  I4 side_ok = (h > 0.0f) & (drdr > 0.0f) & (disc >= 0.0f);
  F4 q = vsqrt(disc / drdr);
  F4 lo = s0 - q, hi = s0 + q;
  F4 zlo = near_b ? -len : splat(0.0f), zhi = near_b ? splat(0.0f) : len;
  F4 sa = (zlo - pzz) / da, sb = (zhi - pzz) / da;
  I4 tilted = da != 0.0f;
  lo = tilted ? vmax(lo, vmin(sa, sb)) : lo;
  hi = tilted ? vmin(hi, vmax(sa, sb)) : hi;
  lo = (tilted | ((pzz >= zlo) & (pzz <= zhi))) ? lo : inf;
  side_ok = side_ok & (lo <= hi);
  I4 new_in = side_ok & (tn + lo < t_in), new_out = side_ok & (tn + hi > t_out);
  t_in = new_in ? tn + lo : t_in;
  s_in = new_in ? lo : s_in;
  e_in = new_in ? nb : e_in;
  t_out = new_out ? tn + hi : t_out;
  s_out = new_out ? hi : s_out;
  e_out = new_out ? nb : e_out;
  // The entry, or (from inside) the exit, within the window.
  I4 take_in = (t_in >= tlo) & (t_in <= tmax);
  I4 hit = ok & (t_in <= t_out) & (take_in | ((t_out >= tlo) & (t_out <= tmax)));
  I4 e = take_in ? e_in : e_out;
  I4 eb = e != 0;
  F4 sh = take_in ? s_in : s_out;
  F4 xx = (eb ? pbx : pax) + sh * d.x, xy = (eb ? pby : pay) + sh * d.y, xz = (eb ? pbz : paz) + sh * d.z;
  F4 z = vdot(xx, xy, xz, wx, wy, wz);
  F4 zn = eb ? z : -z;
  F4 nx = xx - z * wx, ny = xy - z * wy, nz = xz - z * wz;
  F4 u = eb ? 1.0f + z / len : z / len;
  I4 this_end = (zn >= 0.0f) | (h == 0.0f);
  I4 other_end = ~this_end & (zn <= -len);
  nx = this_end ? xx : (other_end ? (eb ? xx + bax : xx - bax) : nx);
  ny = this_end ? xy : (other_end ? (eb ? xy + bay : xy - bay) : ny);
  nz = this_end ? xz : (other_end ? (eb ? xz + baz : xz - baz) : nz);
  u = this_end ? (eb ? splat(1.0f) : splat(0.0f)) : (other_end ? (eb ? splat(0.0f) : splat(1.0f)) : u);
  u = vmin(vmax(u, splat(0.0f)), splat(1.0f));
  F4 t = take_in ? t_in : t_out;
  std::memcpy(out.t, &t, sizeof out.t);
  std::memcpy(out.hit, &hit, sizeof out.hit);
  std::memcpy(out.nx, &nx, sizeof out.nx);
  std::memcpy(out.ny, &ny, sizeof out.ny);
  std::memcpy(out.nz, &nz, sizeof out.nz);
  std::memcpy(out.u, &u, sizeof out.u);
  return out;
}

} // namespace masq::kernel::simd
#endif
#endif
