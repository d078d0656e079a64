// Ray/capsule, fast: Inigo Quilez's closed form (iquilezles.org, "capsule - intersection")
// as written: one quadratic for the infinite cylinder in the ray's own origin frame,
//   a = baba*dd - bard^2, b = baba*rdoa - baoa*bard, c = baba*ooa - baoa^2 - r^2*baba,
// h = b^2 - a*c, and the caps as spheres b^2 - dd*c about the end points.
// Adapted only as far as the common contract needs: dd = dot(d,d) where Quilez assumes
// |d| = 1 (t in units of d), both roots (a ray starting inside reports its exit), both
// caps with their outer-hemisphere tests (Quilez picks one cap from the entry root),
// [tmin, tmax], and radius 0/NaN = miss. No self-intersection window.
// Its digits go for thin, long or distant capsules: b^2 - a*c is a difference of terms
// ~ (baba |o-a|^2)^2 whose true value is ~ (baba r^2)^2 at the silhouette. The robust
// version is intersect_capsule.h.
#ifndef MASQ_KERNEL_INTERSECT_CAPSULE_FAST_H
#define MASQ_KERNEL_INTERSECT_CAPSULE_FAST_H
#include "prim_hit.h"

KERNEL_NS_BEGIN

FN PrimHit intersect_capsule_fast(Capsule cap, vec3 ro, vec3 rd, float tmin, float tmax) {
  PrimHit res = prim_miss();
  res.t = tmax;
  float ra = cap.radius;
  if (!(ra > 0.0f)) return prim_miss();
  vec3 pa = V3(cap.a);
  vec3 pb = V3(cap.b);
  vec3 ba = pb - pa;
  vec3 oa = ro - pa;
  float dd = dot(rd, rd);
  float baba = dot(ba, ba);
  float bard = dot(ba, rd);
  float baoa = dot(ba, oa);
  float rdoa = dot(rd, oa);
  float oaoa = dot(oa, oa);
  float a = baba * dd - bard * bard;
  float b = baba * rdoa - baoa * bard;
  float c = baba * oaoa - baoa * baoa - ra * ra * baba;
  float h = b * b - a * c;
  // The caps lie inside the infinite cylinder: no cylinder crossing, no hit at all.
  // (A zero-length capsule has a = b = c = 0, h = 0: only the cap spheres remain.)
  if (h >= 0.0f) {
    float sh = sqrt(h);
    // body
    for (int k = 0; k < 2; ++k) {
      float t = (k == 0 ? -b - sh : -b + sh) / a;
      float y = baoa + t * bard;
      if (y > 0.0f && y < baba) res = prim_take(res, t, tmin, oa + t * rd - ba * (y / baba), y / baba);
    }
    // caps
    for (int e = 0; e < 2; ++e) {
      vec3 oc = e == 0 ? oa : ro - pb;
      float cb = dot(rd, oc);
      float cc = dot(oc, oc) - ra * ra;
      float ch = cb * cb - dd * cc;
      if (ch > 0.0f) {
        float sch = sqrt(ch);
        for (int k = 0; k < 2; ++k) {
          float t = (k == 0 ? -cb - sch : -cb + sch) / dd;
          float y = baoa + t * bard;
          if (e == 0 ? y <= 0.0f : y >= baba) res = prim_take(res, t, tmin, oc + t * rd, e == 0 ? 0.0f : 1.0f);
        }
      }
    }
  }
  if (res.hit == 0) return prim_miss();
  return res;
}
KERNEL_NS_END
#endif
