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

// The running nearest crossing of each lane (prim_take, lane-wise).
struct Best4 {
  F4 t, nx, ny, nz, u;
  I4 hit;
  void take(I4 cond, F4 tc, F4 tlo, F4 cx, F4 cy, F4 cz, F4 uc) {
    I4 acc = cond & (tc >= tlo) & (tc <= t);
    t = acc ? tc : t;
    nx = acc ? cx : nx;
    ny = acc ? cy : ny;
    nz = acc ? cz : nz;
    u = acc ? uc : u;
    hit = hit | acc;
  }
};

// Capsules c[0..n-1] (n in 1..4) against the ray (o, d) within [tmin, tmax].
inline CapsuleHits4 capsule_hits4(const Capsule* c, int n, glm::vec3 o, glm::vec3 d, float tmin, float tmax) {
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
  I4 long_axis = len > 0.0f;
  F4 wx = long_axis ? bax / len : splat(0.0f);
  F4 wy = long_axis ? bay / len : splat(0.0f);
  F4 wz = long_axis ? baz / len : splat(1.0f);
  F4 ocx = (o.x - ax) - 0.5f * bax, ocy = (o.y - ay) - 0.5f * bay, ocz = (o.z - az) - 0.5f * baz;
  F4 self = (MASQ_SELF_REL * r + 32.0f * MASQ_U * (vsqrt(vdot(ocx, ocy, ocz, ocx, ocy, ocz)) + len)) / std::sqrt(dd);
  F4 tlo = vmax(splat(tmin), self);
  F4 ts = -vdot(ocx, ocy, ocz, splat(d.x), splat(d.y), splat(d.z)) / dd;
  F4 px = ocx + ts * d.x, py = ocy + ts * d.y, pz = ocz + ts * d.z;
  F4 seam = MASQ_CAPSULE_SEAM * (h + r);
  // Most leaves are crossed without a hit. Every crossing lies within h + r of
  // the centre, and p is the line's closest point to it up to the rounding of ts and p
  // (bounded by the 64u term): when every lane's line passes farther, even with 1% to
  // spare, every scalar call misses too, and the rest is skipped. Otherwise all lanes
  // run in full, so the lanes stay bit-identical to the scalar calls.
  float d1 = std::fabs(d.x) + std::fabs(d.y) + std::fabs(d.z);
  F4 reach = (h + r) * 1.01f + seam + 64.0f * MASQ_U * ((vabs(ocx) + vabs(ocy)) + vabs(ocz) + vabs(ts) * d1);
  I4 near = ok & (vdot(px, py, pz, px, py, pz) <= reach * reach);
  if ((near[0] | near[1] | near[2] | near[3]) == 0) {
    for (int i = 0; i < 4; ++i) out.hit[i] = 0;
    return out;
  }
  // From here every lane performs intersect_capsule's operations in its order.
  F4 oax = o.x - ax, oay = o.y - ay, oaz = o.z - az;
  F4 obx = o.x - bx, oby = o.y - by, obz = o.z - bz;
  F4 ta = -vdot(oax, oay, oaz, splat(d.x), splat(d.y), splat(d.z)) / dd;
  F4 tb = -vdot(obx, oby, obz, splat(d.x), splat(d.y), splat(d.z)) / dd;
  F4 pax = oax + ta * d.x, pay = oay + ta * d.y, paz = oaz + ta * d.z;
  F4 pbx = obx + tb * d.x, pby = oby + tb * d.y, pbz = obz + tb * d.z;
  F4 da = vdot(splat(d.x), splat(d.y), splat(d.z), wx, wy, wz);
  Best4 best{splat(tmax), F4{}, F4{}, F4{}, F4{}, I4{}};
  // Side in the axis frame of the nearer endpoint.
  I4 near_b = vdot(pbx, pby, pbz, pbx, pby, pbz) < vdot(pax, pay, paz, pax, pay, paz);
  F4 pex = near_b ? pbx : pax, pey = near_b ? pby : pay, pez = near_b ? pbz : paz;
  F4 te = near_b ? tb : ta;
  F4 sd = near_b ? splat(1.0f) : splat(-1.0f);
  F4 pzz = vdot(pex, pey, pez, wx, wy, wz);
  F4 prx = pex - pzz * wx, pry = pey - pzz * wy, prz = pez - pzz * wz;
  F4 drx = d.x - da * wx, dry = d.y - da * wy, drz = d.z - da * wz;
  F4 drdr = vdot(drx, dry, drz, drx, dry, drz);
  F4 s0 = -vdot(prx, pry, prz, drx, dry, drz) / drdr;
  F4 vx = prx + s0 * drx, vy = pry + s0 * dry, vz = prz + s0 * drz;
  F4 lv = vsqrt(vdot(vx, vy, vz, vx, vy, vz));
  F4 disc = (r - lv) * (r + lv);
  I4 side_ok = ok & (h > 0.0f) & (drdr > 0.0f) & (disc >= 0.0f);
  F4 q = vsqrt(disc / drdr);
  for (int k = 0; k < 2; ++k) {
    F4 s = k == 0 ? s0 - q : s0 + q;
    F4 z = sd * (pzz + s * da);
    F4 u = vmin(vmax(near_b ? 1.0f + z / len : -z / len, splat(0.0f)), splat(1.0f));
    best.take(side_ok & (z <= 0.0f) & (z >= -len), te + s, tlo, prx + s * drx, pry + s * dry, prz + s * drz, u);
  }
  // Caps: balls at the two ends, each in its endpoint's frame, outer hemisphere only.
  for (int e = 0; e < 2; ++e) {
    float side = e == 0 ? -1.0f : 1.0f;
    F4 pcx = e == 0 ? pax : pbx, pcy = e == 0 ? pay : pby, pcz = e == 0 ? paz : pbz;
    F4 tc = e == 0 ? ta : tb;
    F4 c0 = -vdot(pcx, pcy, pcz, splat(d.x), splat(d.y), splat(d.z)) / dd;
    F4 ux = pcx + c0 * d.x, uy = pcy + c0 * d.y, uz = pcz + c0 * d.z;
    F4 lc = vsqrt(vdot(ux, uy, uz, ux, uy, uz));
    F4 dc = (r - lc) * (r + lc);
    I4 cap_ok = ok & (dc >= 0.0f);
    F4 qc = vsqrt(dc / dd);
    for (int k = 0; k < 2; ++k) {
      F4 s = k == 0 ? c0 - qc : c0 + qc;
      F4 nx = pcx + s * d.x, ny = pcy + s * d.y, nz = pcz + s * d.z;
      best.take(cap_ok & ((h == 0.0f) | (side * vdot(nx, ny, nz, wx, wy, wz) >= -seam)), tc + s, tlo, nx, ny, nz,
                splat(e == 0 ? 0.0f : 1.0f));
    }
  }
  std::memcpy(out.t, &best.t, sizeof out.t);
  std::memcpy(out.hit, &best.hit, sizeof out.hit);
  std::memcpy(out.nx, &best.nx, sizeof out.nx);
  std::memcpy(out.ny, &best.ny, sizeof out.ny);
  std::memcpy(out.nz, &best.nz, sizeof out.nz);
  std::memcpy(out.u, &best.u, sizeof out.u);
  return out;
}

} // namespace masq::kernel::simd
#endif
#endif
