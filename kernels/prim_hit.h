// What every primitive intersector returns: the nearest surface point with t in
// [tmin, tmax], in the space of the ray it was given.
#ifndef MASQ_KERNEL_PRIM_HIT_H
#define MASQ_KERNEL_PRIM_HIT_H
#include "math.h"

KERNEL_NS_BEGIN
STRUCT_BEGIN(PrimHit)
  int hit;
  float t;
  vec3 normal; // unnormalised geometric normal
  float u;
  float v;
STRUCT_END(PrimHit)

// Self-intersection window. A ray spawned on a surface (a secondary ray from a hit
// point, tmin = 0) must not report the surface it starts on; fp32 cannot tell such a
// crossing from a genuine one within the rounding error of the origin relative to the
// primitive. So every robust intersector ignores crossings closer than
//   t_self = (2^-10 * r + 32u * (|o - c| + span)) / |d|
// (r: the primitive's radius, c: its centre, span: its length (capsule, cone: |b - a|;
// curve: the control polygon's length; sphere, triangle: 0), since the intersectors'
// own rounding grows with both; every term scales with the primitive, not with the
// distance to the world origin). The oracle applies the same rule.
#define MASQ_SELF_REL 9.765625e-4f
FN float self_eps_t_span(float r, vec3 oc, float span, float dd) {
  return (MASQ_SELF_REL * r + 32.0f * MASQ_U * (length(oc) + span)) / sqrt(dd);
}
FN float self_eps_t(float r, vec3 oc, float dd) { return self_eps_t_span(r, oc, 0.0f, dd); }

FN PrimHit prim_miss() {
  PrimHit h;
  h.hit = 0;
  h.t = inf_();
  h.normal = VEC3(0.0f, 0.0f, 0.0f);
  h.u = 0.0f;
  h.v = 0.0f;
  return h;
}
// A crossing at t (normal n, axial/curve parameter u) becomes the result if it lies in
// [tmin, best.t]: the intersectors search nearest-first within the current best.
FN PrimHit prim_take(PrimHit best, float t, float tmin, vec3 n, float u) {
  if (t >= tmin && t <= best.t) {
    best.hit = 1;
    best.t = t;
    best.normal = n;
    best.u = u;
    best.v = 0.0f;
  }
  return best;
}

// A ray against a ball of radius r: p is the ray origin relative to the ball's centre,
// d the direction, dd = dot(d, d). The crossings are s0 -+ q in the ray's parameter from
// that origin, formed at the closest approach v = p + s0 d so that the discriminant
// (r - |v|)(r + |v|) is exact to a few ulps of r^2 however far the origin is
// (intersect_sphere.h). found = 0 where the ray misses (or the discriminant is NaN).
// Also the circle of a cylinder's cross-section (p and d projected off its axis).
STRUCT_BEGIN(BallSpan)
  int found;
  float s0;
  float q;
  vec3 v;
STRUCT_END(BallSpan)

FN BallSpan ball_span(vec3 p, float r, vec3 d, float dd) {
  BallSpan b;
  b.s0 = -dot(p, d) / dd;
  b.v = p + b.s0 * d;
  float lv = length(b.v);
  float disc = (r - lv) * (r + lv);
  b.found = disc >= 0.0f ? 1 : 0;
  b.q = b.found != 0 ? sqrt(disc / dd) : 0.0f;
  return b;
}

KERNEL_NS_END
#endif
