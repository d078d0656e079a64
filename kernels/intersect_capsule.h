// Ray/capsule (constant-radius segment with spherical caps), robust form.
// Quilez's closed form loses most of its digits for thin, long or distant capsules
// (measured: 29-44% wrong silhouette rays at r = 1e-4). This version
//  1. moves the origin to the ray's closest approach to an ENDPOINT (o - a or o - b:
//     one rounding of a difference of inputs, so no error proportional to the distance
//     of the capsule from the world origin), so every later quantity is of the size of
//     the ray's distance from that endpoint, not of the distance travelled;
//  2. solves each end cap in its own endpoint's frame, and the side in the frame of the
//     endpoint the ray passes nearer: a crossing near an end then carries u (D + r), not
//     u (D + L) (the rounding of a centre frame L/2 away; issue 23 measured false cap
//     hits up to 0.12 r outside at L = 1e6 r; docs/robustness.md);
//  3. works in the capsule's axis frame for the side: the axial parts of origin and
//     direction are removed, leaving a 2D circle problem;
//  4. forms each discriminant as (r-|v|)(r+|v|) from the closest-approach vector v,
//     instead of b^2 - c, which cancels catastrophically;
//  5. carries dot(d,d), so non-unit and transformed directions give exact t;
//  6. ignores crossings closer than the self-intersection window t_self (prim_hit.h).
#ifndef MASQ_KERNEL_INTERSECT_CAPSULE_H
#define MASQ_KERNEL_INTERSECT_CAPSULE_H
#include "prim_hit.h"

KERNEL_NS_BEGIN

// Seam tolerance, on the caps only: a cap crossing is accepted up to this fraction of
// h + r inside its inner hemisphere, so that rounding of the side's axial test cannot
// open a gap between side and cap. The whole ball lies inside the capsule, so an
// inner-hemisphere crossing is never outside the surface (at worst it is taken instead
// of the side crossing just before it). The side is not widened: a side crossing
// accepted a distance e past the end lies up to e^2 / 2r outside the cap, and a
// tolerance relative to the length made that 0.12 r at L = 1e6 r.
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
  // 6. self window, from the origin relative to the centre.
  vec3 oc = (o - a) - 0.5f * ba;
  float tlo = max(tmin, self_eps_t_span(r, oc, len, dd));
  // 1. the ray point nearest each endpoint: t = te + s.
  vec3 oa = o - a;
  vec3 ob = o - b;
  float ta = -dot(oa, d) / dd;
  float tb = -dot(ob, d) / dd;
  vec3 pa = oa + ta * d;
  vec3 pb = ob + tb * d;
  float da = dot(d, w);
  float seam = MASQ_CAPSULE_SEAM * (h + r);
  // 2./3./4. side in the axis frame of the nearer endpoint; z: axial coordinate from it,
  // inside the segment when side * z is in [-len, 0].
  if (h > 0.0f) {
    int near_b = dot(pb, pb) < dot(pa, pa) ? 1 : 0;
    vec3 pe = near_b != 0 ? pb : pa;
    float te = near_b != 0 ? tb : ta;
    float side = near_b != 0 ? 1.0f : -1.0f;
    float pz = dot(pe, w);
    vec3 pr = pe - pz * w;
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
          float z = side * (pz + s * da);
          if (z <= 0.0f && z >= -len)
            res = prim_take(res, te + s, tlo, pr + s * dr, min(max(near_b != 0 ? 1.0f + z / len : -z / len, 0.0f), 1.0f));
        }
      }
    }
  }
  // Caps: balls at the two ends, each in its endpoint's frame; a crossing counts on the
  // outer hemisphere only (with the seam overlap inwards).
  for (int e = 0; e < 2; ++e) {
    float side = e == 0 ? -1.0f : 1.0f;
    vec3 pe = e == 0 ? pa : pb;
    float te = e == 0 ? ta : tb;
    float s0 = -dot(pe, d) / dd;
    vec3 v = pe + s0 * d;
    float lv = length(v);
    float disc = (r - lv) * (r + lv);
    if (disc >= 0.0f) {
      float q = sqrt(disc / dd);
      for (int k = 0; k < 2; ++k) {
        float s = k == 0 ? s0 - q : s0 + q;
        vec3 ne = pe + s * d; // outward normal (any length)
        if (h == 0.0f || side * dot(ne, w) >= -seam) res = prim_take(res, te + s, tlo, ne, e == 0 ? 0.0f : 1.0f);
      }
    }
  }
  if (res.hit == 0) return prim_miss();
  return res;
}
KERNEL_NS_END
#endif
