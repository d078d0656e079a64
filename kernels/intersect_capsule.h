// Ray/capsule (constant-radius segment with spherical caps), robust form.
// Quilez's closed form loses most of its digits for thin, long or distant capsules
// (measured: 29-44% wrong silhouette rays at r = 1e-4). This version
//  1. moves the origin to the ray's closest approach to the capsule centre, so every
//     later quantity is of the size of the capsule, not of the distance to it;
//  2. works in the capsule's axis frame: the axial parts of origin and direction are
//     removed, leaving a 2D circle problem;
//  3. forms the discriminant as (r-|v|)(r+|v|) from the closest-approach vector v,
//     instead of b^2 - c, which cancels catastrophically;
//  4. carries dot(d,d), so non-unit and transformed directions give exact t;
//  5. forms o - centre as (o - a) - ba/2: one rounding of a difference of inputs, so no
//     error proportional to the distance of the capsule from the world origin;
//  6. ignores crossings closer than the self-intersection window t_self (prim_hit.h).
#ifndef MASQ_KERNEL_INTERSECT_CAPSULE_H
#define MASQ_KERNEL_INTERSECT_CAPSULE_H
#include "prim_hit.h"

KERNEL_NS_BEGIN

// Seam tolerance: cylinder and cap hits are accepted slightly past the seam so that
// rounding cannot open a gap between them (the surfaces agree there to second order).
#define MASQ_CAPSULE_SEAM 1e-6f

FN PrimHit intersect_capsule(Capsule cap, vec3 o, vec3 d, float tmin, float tmax) {
  PrimHit res = prim_miss();
  res.t = tmax;
  float r = cap.radius;
  float dd = dot(d, d);
  // Zero/negative/NaN radius (no surface), no ray, or an empty/NaN interval: miss.
  if (!(r > 0.0f) || !(dd > 0.0f) || !(tmin <= tmax)) return prim_miss();
  vec3 a = V3(cap.a);
  vec3 b = V3(cap.b);
  vec3 ba = b - a;
  float len = length(ba);
  float h = 0.5f * len;
  vec3 w = len > 0.0f ? ba / len : VEC3(0.0f, 0.0f, 1.0f);
  // 5. origin relative to the centre, 6. self window.
  vec3 oc = (o - a) - 0.5f * ba;
  float tlo = max(tmin, self_eps_t_span(r, oc, len, dd));
  // 1. origin shift: p is the ray point nearest the centre, t = ts + s.
  float ts = -dot(oc, d) / dd;
  vec3 p = oc + ts * d;
  float pa = dot(p, w);
  float da = dot(d, w);
  float seam = MASQ_CAPSULE_SEAM * (h + r);
  // 2./3. cylinder side in the axis frame.
  if (h > 0.0f) {
    vec3 pr = p - pa * w;
    vec3 dr = d - da * w;
    float drdr = dot(dr, dr);
    if (drdr > 0.0f) {
      float s0 = -dot(pr, dr) / drdr;
      vec3 v = pr + s0 * dr;
      float lv = length(v);
      float disc = (r - lv) * (r + lv);
      if (disc >= 0.0f) {
        float q = sqrt(disc / drdr);
        for (int k = 0; k < 2; ++k) {
          float s = k == 0 ? s0 - q : s0 + q;
          float z = pa + s * da;
          if (fabs_(z) <= h + seam) res = prim_take(res, ts + s, tlo, pr + s * dr, min(max((z + h) / len, 0.0f), 1.0f));
        }
      }
    }
  }
  // Caps: spheres at the two ends; a hit counts on the outer hemisphere only.
  for (int e = 0; e < 2; ++e) {
    float side = e == 0 ? -1.0f : 1.0f;
    vec3 pc = p - (side * h) * w;
    float s0 = -dot(pc, d) / dd;
    vec3 v = pc + s0 * d;
    float lv = length(v);
    float disc = (r - lv) * (r + lv);
    if (disc >= 0.0f) {
      float q = sqrt(disc / dd);
      for (int k = 0; k < 2; ++k) {
        float s = k == 0 ? s0 - q : s0 + q;
        float z = pa + s * da;
        if (h == 0.0f || side * z >= h - seam)
          res = prim_take(res, ts + s, tlo, pc + s * d, e == 0 ? 0.0f : 1.0f);
      }
    }
  }
  if (res.hit == 0) return prim_miss();
  return res;
}
KERNEL_NS_END
#endif
