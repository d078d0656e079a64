// Watertight ray/triangle test (Woop, Benthin, Wald 2013): shear the triangle into the
// ray's frame so that adjacent triangles share edge functions exactly; no ray slips
// through a shared edge or vertex. Crossings closer than the self-intersection window
// (prim_hit.h, r = 0, centre v0) are ignored, so a ray leaving a triangle does not
// report it again.
// intersect_triangle_fast: Moller-Trumbore (not watertight, no window).
#ifndef MASQ_KERNEL_INTERSECT_TRIANGLE_H
#define MASQ_KERNEL_INTERSECT_TRIANGLE_H
#include "prim_hit.h"

KERNEL_NS_BEGIN
FN_INLINED PrimHit intersect_triangle(Triangle tri, vec3 o, vec3 d, float tmin, float tmax) {
  PrimHit res = prim_miss();
  float dd = dot(d, d);
  if (!(dd > 0.0f) || !(tmin <= tmax)) return res;
  float tlo = max(tmin, self_eps_t(0.0f, o - V3(tri.v0), dd));
  vec3 ad = vabs_(d);
  int kz = (ad.x >= ad.y && ad.x >= ad.z) ? 0 : (ad.y >= ad.z ? 1 : 2);
  int kx = kz == 2 ? 0 : kz + 1;
  int ky = kx == 2 ? 0 : kx + 1;
  float dz = vcomp(d, kz);
  if (dz < 0.0f) {
    int tmp = kx;
    kx = ky;
    ky = tmp;
  }
  float sx = vcomp(d, kx) / dz;
  float sy = vcomp(d, ky) / dz;
  vec3 a = V3(tri.v0) - o;
  vec3 b = V3(tri.v1) - o;
  vec3 c = V3(tri.v2) - o;
  float ax = vcomp(a, kx) - sx * vcomp(a, kz);
  float ay = vcomp(a, ky) - sy * vcomp(a, kz);
  float bx = vcomp(b, kx) - sx * vcomp(b, kz);
  float by = vcomp(b, ky) - sy * vcomp(b, kz);
  float cx = vcomp(c, kx) - sx * vcomp(c, kz);
  float cy = vcomp(c, ky) - sy * vcomp(c, kz);
  float eu = cx * by - cy * bx;
  float ev = ax * cy - ay * cx;
  float ew = bx * ay - by * ax;
  if ((eu < 0.0f || ev < 0.0f || ew < 0.0f) && (eu > 0.0f || ev > 0.0f || ew > 0.0f)) return res;
  float det = eu + ev + ew;
  if (det == 0.0f) return res;
  float sz = 1.0f / dz;
  float az = sz * vcomp(a, kz);
  float bz = sz * vcomp(b, kz);
  float cz = sz * vcomp(c, kz);
  float tt = eu * az + ev * bz + ew * cz;
  if (det < 0.0f) {
    tt = -tt;
    det = -det;
    eu = -eu;
    ev = -ev;
    ew = -ew;
  }
  if (!(tt >= tlo * det && tt <= tmax * det)) return res;
  // A ray starting on the triangle's plane (within 16u of |o - v0| + |v0|: the
  // rounding of a hit point spawned there, whose coordinates are as large as v0's)
  // cannot cross that plane again; oblique rays would otherwise re-hit it beyond the t
  // window (the error in t grows as 1/cos of the angle to the normal, the plane
  // distance does not).
  vec3 nrm = cross(V3(tri.v1) - V3(tri.v0), V3(tri.v2) - V3(tri.v0));
  vec3 ov = o - V3(tri.v0);
  if (fabs_(dot(ov, nrm)) <= 16.0f * MASQ_U * (length(ov) + length(V3(tri.v0))) * length(nrm)) return res;
  float inv_det = 1.0f / det;
  res.hit = 1;
  res.t = tt * inv_det;
  res.u = ev * inv_det;
  res.v = ew * inv_det;
  res.normal = nrm;
  return res;
}

FN PrimHit intersect_triangle_fast(Triangle tri, vec3 o, vec3 d, float tmin, float tmax) {
  PrimHit res = prim_miss();
  vec3 v0 = V3(tri.v0);
  vec3 e1 = V3(tri.v1) - v0;
  vec3 e2 = V3(tri.v2) - v0;
  vec3 pv = cross(d, e2);
  float det = dot(e1, pv);
  if (det == 0.0f) return res;
  float inv_det = 1.0f / det;
  vec3 tv = o - v0;
  float bu = dot(tv, pv) * inv_det;
  if (bu < 0.0f || bu > 1.0f) return res;
  vec3 qv = cross(tv, e1);
  float bv = dot(d, qv) * inv_det;
  if (bv < 0.0f || bu + bv > 1.0f) return res;
  float t = dot(e2, qv) * inv_det;
  if (!(t >= tmin && t <= tmax)) return res;
  res.hit = 1;
  res.t = t;
  res.u = bu;
  res.v = bv;
  res.normal = cross(e1, e2);
  return res;
}
KERNEL_NS_END
#endif
