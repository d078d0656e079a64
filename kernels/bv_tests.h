// Conservative ray tests of the binary hierarchies' node volumes (kernels/bv_layout.h).
// Each returns a LOWER BOUND of the ray's entry distance into the volume within
// [tmin, tmax], or +inf when the ray provably misses it: fp32 rounding may let a miss
// through, never reject a hit. The padding terms are derived in docs/robustness.md
// ("Bounding-volume tests"): every quantity is at most a few roundings of terms bounded
// by |m| = |o - c| and the reach |m| + extent of the volume, so a relative pad of
// MASQ_BV_PAD on those sums covers them on every backend (division error included).
#ifndef MASQ_KERNEL_BV_TESTS_H
#define MASQ_KERNEL_BV_TESTS_H
#include "box.h"

// 8 gamma_4 (~1.9e-6): well above the few-ulp sums the derivation needs.
#define MASQ_BV_PAD (8.0f * MASQ_GAMMA4)

KERNEL_NS_BEGIN

FN float l1_(vec3 v) { return fabs_(v.x) + fabs_(v.y) + fabs_(v.z); }

// A ray with what the tests precompute once: inv_d (safe_rcp3), rcp_dd = 1/dot(d, d),
// rl = 1/|d|.
STRUCT_BEGIN(BvRay)
  vec3 o;
  vec3 d;
  vec3 inv_d;
  float rcp_dd;
  float rl;
STRUCT_END(BvRay)

FN BvRay bv_ray(vec3 o, vec3 d) {
  BvRay r;
  r.o = o;
  r.d = d;
  r.inv_d = safe_rcp3(d);
  float dd = dot(d, d);
  r.rcp_dd = 1.0f / dd;
  r.rl = 1.0f / sqrt(dd);
  return r;
}

// Axis-aligned box: the slab test of the wide nodes (Ize 2013 widening).
FN float bv_hit_aabb(BvNodeAabb n, BvRay ray, float tmin, float tmax) {
  vec3 o = ray.o;
  vec3 inv_d = ray.inv_d;
  float tx0 = (n.lo[0] - o.x) * inv_d.x;
  float tx1 = (n.hi[0] - o.x) * inv_d.x;
  float ty0 = (n.lo[1] - o.y) * inv_d.y;
  float ty1 = (n.hi[1] - o.y) * inv_d.y;
  float tz0 = (n.lo[2] - o.z) * inv_d.z;
  float tz1 = (n.hi[2] - o.z) * inv_d.z;
  float tn = widen_lo(vmax3_(min(tx0, tx1), min(ty0, ty1), min(tz0, tz1)));
  float tf = widen_hi(vmin3_(max(tx0, tx1), max(ty0, ty1), max(tz0, tz1)));
  return (tn <= tf && tf >= tmin && tn <= tmax) ? max(tn, tmin) : inf_();
}

// A lower bound of the entry when the point at ts (inside the ball of radius r) is on
// the ray: the entry point and that point both lie in the ball, so they are at most
// 2r apart. rl: 1/|d|.
FN float ball_entry_bound(float ts, float r, float rl, float lo) {
  return max(lo, ts - 2.0f * r * rl * (1.0f + 16.0f * MASQ_U) - 16.0f * MASQ_U * fabs_(ts));
}

// Ball: the closest point of the ray segment [tmin, tmax] to the centre must be within
// the (padded) radius. rcp_dd: 1/dot(d, d); rl: 1/|d|.
FN float bv_hit_sphere(BvNodeSphere n, BvRay ray, float tmin, float tmax) {
  vec3 d = ray.d;
  vec3 m = ray.o - V3(n.center);
  float tc = -dot(m, d) * ray.rcp_dd;
  float ts = min(max(tc, tmin), tmax);
  vec3 p = m + ts * d;
  float r = (n.radius + MASQ_BV_PAD * (l1_(m) + fabs_(ts) * l1_(d))) * (1.0f + 4.0f * MASQ_U);
  if (dot(p, p) > r * r) return inf_();
  return ball_entry_bound(ts, r, ray.rl, tmin);
}

// One slab {x : lo <= dot(a, x - c) <= hi} clipped into [tn, tf]; a miss makes tn > tf.
// am: |o - c| componentwise; reach: a bound of |x - o| for x in the volume.
STRUCT_BEGIN(SlabClip)
  float tn;
  float tf;
STRUCT_END(SlabClip)

FN SlabClip clip_slab(SlabClip s, vec3 a, float lo, float hi, vec3 m, vec3 d, float reach) {
  float om = dot(a, m);
  float dm = dot(a, d);
  // Error of om + t*dm for |t d| <= reach (|a| ~ 1): gamma_4 |a|.|m| + gamma_3 reach.
  float pad = MASQ_BV_PAD * (dot(vabs_(a), vabs_(m)) + reach);
  float plo = lo - pad - fabs_(lo) * 2.0f * MASQ_U;
  float phi = hi + pad + fabs_(hi) * 2.0f * MASQ_U;
  if (dm == 0.0f) {
    // Parallel: inside for every t or for none (no 0/0 or inf*0 to get wrong).
    if (om < plo || om > phi) s.tn = inf_();
    return s;
  }
  float t0 = (plo - om) / dm;
  float t1 = (phi - om) / dm;
  s.tn = max(s.tn, widen_lo(min(t0, t1)));
  s.tf = min(s.tf, widen_hi(max(t0, t1)));
  return s;
}

// Oriented box: three slabs about the centre.
FN float bv_hit_obb(BvNodeObb n, BvRay ray, float tmin, float tmax) {
  vec3 d = ray.d;
  vec3 m = ray.o - V3(n.center);
  // Inside the box |x - c| <= |half|_1 (axes ~unit), so |x - o| <= reach.
  float reach = l1_(m) + n.half0 + n.half1 + n.half2;
  SlabClip s;
  s.tn = tmin;
  s.tf = tmax;
  s = clip_slab(s, V3(n.axis0), -n.half0, n.half0, m, d, reach);
  s = clip_slab(s, V3(n.axis1), -n.half1, n.half1, m, d, reach);
  s = clip_slab(s, V3(n.axis2), -n.half2, n.half2, m, d, reach);
  return s.tn <= s.tf ? s.tn : inf_();
}

// Slab cut ball, in the order of Kallberg & Larsson's routine: inside test, ball
// reject, slab interval, closest point clamp. No square root on the way to the answer.
FN float bv_hit_scb(BvNodeScb n, BvRay ray, float tmin, float tmax) {
  vec3 d = ray.d;
  vec3 m = ray.o - V3(n.center);
  float lm = l1_(m);
  float mm = dot(m, m);
  float md = dot(m, d);
  float r0 = (n.radius + MASQ_BV_PAD * lm) * (1.0f + 4.0f * MASQ_U); // padded radius at t = 0
  bool out_ball0 = mm > r0 * r0;
  vec3 nn = V3(n.normal);
  float mn = dot(m, nn);
  float ps0 = MASQ_BV_PAD * dot(vabs_(nn), vabs_(m));
  // 1. Inside: the origin (t = 0, when 0 is in [tmin, tmax]) lies in the ball and the slab.
  if (tmin <= 0.0f && tmax >= 0.0f && !out_ball0 && mn >= n.f - ps0 - fabs_(n.f) * 2.0f * MASQ_U &&
      mn <= n.e + ps0 + fabs_(n.e) * 2.0f * MASQ_U)
    return tmin;
  // 2. Ball reject: outside the ball and moving away (for t >= 0 only).
  if (tmin >= 0.0f && out_ball0 && md > MASQ_BV_PAD * dot(vabs_(m), vabs_(d))) return inf_();
  // 3. Slab interval, intersected with [tmin, tmax].
  SlabClip s;
  s.tn = tmin;
  s.tf = tmax;
  s = clip_slab(s, nn, n.f, n.e, m, d, lm + n.radius);
  if (s.tn > s.tf) return inf_();
  // 4. Closest point clamp: the point of the clipped segment nearest the centre.
  float ts = min(max(-md * ray.rcp_dd, s.tn), s.tf);
  vec3 p = m + ts * d;
  float r = (n.radius + MASQ_BV_PAD * (lm + fabs_(ts) * l1_(d))) * (1.0f + 4.0f * MASQ_U);
  if (dot(p, p) > r * r) return inf_();
  return ball_entry_bound(ts, r, ray.rl, s.tn);
}

KERNEL_NS_END
#endif
