// Ray/ribbon (kernels/layout.h, Ribbon: a flat, normal-oriented linear strip), robust and
// fast. The strip lies in the plane through the axis p0 -> p1 spanned by the axis and
// the width direction w = normalize(cross(n, p1 - p0)); a point q of that plane is on
// the ribbon when its axial parameter s is in [0, 1] and |dot(q - axis(s), w)| <= r(s),
// r(s) = r0 + s (r1 - r0).
// Robust:
//  1. everything is measured from p0 in the unit frame (axis, w, plane normal), so no
//     product grows with the distance to the world origin, and the plane distance of
//     the origin is one dot product of sizes |o - p0|;
//  2. t from that distance leaves the ray point o + t d off the plane by the rounding
//     of t d; one correction step from that point (whose plane distance is small)
//     removes it, so s and the width coordinate are those of the plane crossing;
//  3. a normal within 2^-12 rad of the axis has no usable width direction in fp32 (the
//     cross product is all rounding): such a ribbon has no surface, as the oracle says;
//  4. the self window (prim_hit.h: r = 0, span |p1 - p0|) and the triangles' plane rule
//     (an origin on the plane never hits: a ray leaving the ribbon cannot cross it again).
// Fast: the textbook plane crossing in world coordinates with unnormalised cross
// products, no window, for comparison and speed measurements.
#ifndef MASQ_KERNEL_INTERSECT_RIBBON_H
#define MASQ_KERNEL_INTERSECT_RIBBON_H
#include "prim_hit.h"

// sin^2 of the smallest angle between normal and axis that still defines a width
// direction: 2^-24 (2^-12 rad). The oracle uses the same bound.
#define MASQ_RIBBON_MIN_SIN2 5.9604645e-8f

KERNEL_NS_BEGIN
FN PrimHit intersect_ribbon(Ribbon rb, vec3 o, vec3 d, float tmin, float tmax) {
  PrimHit res = prim_miss();
  float dd = dot(d, d);
  if (!(dd > 0.0f) || !(tmin <= tmax)) return res;
  vec3 p0 = V3(rb.p0);
  vec3 a = V3(rb.p1) - p0;
  float aa = dot(a, a);
  if (!(aa > 0.0f) || !(max(rb.r0, rb.r1) > 0.0f)) return res; // no axis or no width: no surface
  float la = sqrt(aa);
  vec3 ax = a / la;
  vec3 w = cross(V3(rb.n), ax);
  float ww = dot(w, w);
  if (!(ww > MASQ_RIBBON_MIN_SIN2)) return res;
  w = w / sqrt(ww);
  vec3 nrm = cross(ax, w); // unit, on n's side of the plane
  // From p0, a point the ribbon holds exactly: a rounded midpoint would shift s and the
  // width coordinate by u |p0|, which far from the world origin exceeds the width.
  vec3 op = o - p0;
  float dn = dot(d, nrm);
  if (dn == 0.0f) return res; // parallel to the plane
  float h = dot(op, nrm);
  // An origin on the plane (within 16u of |o - c| + |p0| + |p1 - p0|: the rounding of a
  // hit point spawned there) cannot cross it again.
  vec3 oc = op - 0.5f * a;
  if (fabs_(h) <= 16.0f * MASQ_U * (length(oc) + length(p0) + la)) return res;
  float t = -h / dn;
  vec3 q = op + t * d;
  t = t - dot(q, nrm) / dn;
  q = op + t * d;
  float s = dot(q, ax) / la;
  float v = dot(q, w);
  float r = max(rb.r0 + s * (rb.r1 - rb.r0), 0.0f);
  if (!(s >= 0.0f && s <= 1.0f && fabs_(v) <= r)) return res;
  float tlo = max(tmin, self_eps_t_span(0.0f, oc, la, dd));
  if (!(t >= tlo && t <= tmax)) return res;
  res.hit = 1;
  res.t = t;
  res.normal = nrm;
  res.u = s;
  res.v = r > 0.0f ? v / r : 0.0f;
  return res;
}

FN PrimHit intersect_ribbon_fast(Ribbon rb, vec3 o, vec3 d, float tmin, float tmax) {
  PrimHit res = prim_miss();
  vec3 p0 = V3(rb.p0);
  vec3 a = V3(rb.p1) - p0;
  vec3 w = cross(V3(rb.n), a);
  vec3 nrm = cross(a, w);
  float aa = dot(a, a);
  float ww = dot(w, w);
  if (!(aa > 0.0f) || !(ww > MASQ_RIBBON_MIN_SIN2 * aa)) return res;
  float dn = dot(d, nrm);
  if (dn == 0.0f) return res;
  float t = dot(p0 - o, nrm) / dn;
  if (!(t >= tmin && t <= tmax)) return res;
  vec3 q = o + t * d - p0;
  float s = dot(q, a) / aa;
  float v = dot(q, w) / sqrt(ww);
  float r = rb.r0 + s * (rb.r1 - rb.r0);
  if (!(s >= 0.0f && s <= 1.0f && fabs_(v) <= r && r > 0.0f)) return res;
  res.hit = 1;
  res.t = t;
  res.normal = nrm;
  res.u = s;
  res.v = v / r;
  return res;
}
KERNEL_NS_END
#endif
