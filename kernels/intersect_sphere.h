// Ray/sphere, robust and fast.
// Robust: the textbook discriminant b^2 - c cancels catastrophically for a small
// sphere seen from far away (both terms ~ |o-c|^2, their difference ~ r^2), so
//  1. the origin is moved along the ray to its closest approach p to the centre (every
//     later quantity is of the size of the sphere, not of the distance to it);
//  2. the discriminant is (r-|p|)(r+|p|), exact up to a few ulps of r^2;
//  3. in the shifted frame the quadratic is s^2 dd = disc: its roots are the symmetric
//     pair +-sqrt(disc/dd), so the stable-root form q = -(b + sign(b) sqrt(disc)) has
//     b = 0 and nothing left to cancel; the normal p + s d needs no large t;
//  4. dot(d,d) is carried, so non-unit and transformed directions give exact t.
// Fast: the textbook b^2 - dd*c, for comparison and speed measurements.
#ifndef MASQ_KERNEL_INTERSECT_SPHERE_H
#define MASQ_KERNEL_INTERSECT_SPHERE_H
#include "prim_hit.h"

KERNEL_NS_BEGIN

// Nearest crossing in [tlo, tmax] of the sphere of radius r centred at o - oc (oc: the
// ray origin relative to the centre, formed by the caller). u = v = 0.
FN PrimHit sphere_hit_robust(vec3 oc, float r, vec3 d, float dd, float tlo, float tmax) {
  PrimHit res = prim_miss();
  BallSpan b = ball_span(oc, r, d, dd);
  if (b.found == 0) return res;
  float ts = b.s0;
  vec3 p = b.v;
  float q = b.q;
  // Near root first: the first accepted one is the nearest.
  for (int k = 0; k < 2; ++k) {
    float s = k == 0 ? -q : q;
    float t = ts + s;
    if (res.hit == 0 && t >= tlo && t <= tmax) {
      res.hit = 1;
      res.t = t;
      res.normal = p + s * d;
    }
  }
  return res;
}

FN PrimHit intersect_sphere(Sphere sp, vec3 o, vec3 d, float tmin, float tmax) {
  float r = sp.radius;
  float dd = dot(d, d);
  // No surface, no ray, or an empty/NaN interval: miss (the comparisons reject NaN).
  if (!(r > 0.0f) || !(dd > 0.0f) || !(tmin <= tmax)) return prim_miss();
  vec3 oc = o - V3(sp.center);
  float tlo = max(tmin, self_eps_t(r, oc, dd));
  return sphere_hit_robust(oc, r, d, dd, tlo, tmax);
}

// Textbook: t = (-b -+ sqrt(b^2 - dd c)) / dd with b = oc.d, c = oc.oc - r^2.
FN PrimHit sphere_hit_fast(vec3 oc, float r, vec3 d, float dd, float tmin, float tmax) {
  PrimHit res = prim_miss();
  float b = dot(oc, d);
  float c = dot(oc, oc) - r * r;
  float h = b * b - dd * c;
  if (!(h >= 0.0f)) return res;
  float sh = sqrt(h);
  for (int k = 0; k < 2; ++k) {
    float t = (k == 0 ? -b - sh : -b + sh) / dd;
    if (res.hit == 0 && t >= tmin && t <= tmax) {
      res.hit = 1;
      res.t = t;
      res.normal = oc + t * d;
    }
  }
  return res;
}

FN PrimHit intersect_sphere_fast(Sphere sp, vec3 o, vec3 d, float tmin, float tmax) {
  float r = sp.radius;
  float dd = dot(d, d);
  if (!(r > 0.0f) || !(dd > 0.0f)) return prim_miss();
  return sphere_hit_fast(o - V3(sp.center), r, d, dd, tmin, tmax);
}
KERNEL_NS_END
#endif
