// Fast mode's curve intersector core: the phantom iteration of Reshetov & Luebke,
// "Phantom Ray-Hair Intersector" (HPG 2018), as written in the paper (see
// kernels/intersect_curve.h for what each mode does).
#ifndef MASQ_KERNEL_CURVE_PHANTOM_H
#define MASQ_KERNEL_CURVE_PHANTOM_H
#include "curve_frame.h"
#include "variants.h" // MASQ_CURVE_ITERS

// Fast: the paper's |ds| bound in curve-parameter units.
#define MASQ_CURVE_FAST_TOL 5e-5f
// Fast: overlap of the end balls' outer hemispheres and the tube at the seam (times r).
#define MASQ_CURVE_SEAM 9.765625e-4f

KERNEL_NS_BEGIN

// One phantom step at s (the paper's): the ray against the cylinder of radius r about
// the tangent line at C(s). side -1: its near root (entry), +1: its far root (exit).
STRUCT_BEGIN(CurveStep)
  int ok;      // tangent usable (not zero, not parallel to the ray)
  int real;    // the ray meets the cylinder
  float z;     // the ray's crossing of the cylinder (closest approach if none)
  float g;     // update of s
  vec3 nrm;    // outward normal at the crossing (frame coordinates)
STRUCT_END(CurveStep)

FN CurveStep curve_step(CurveFrame f, float s, float side) {
  CurvePoint e = curve_eval(f, s);
  vec3 c0 = e.p;
  vec3 cd = e.d;
  CurveStep st;
  st.ok = 0;
  st.real = 0;
  st.z = 0.0f;
  st.g = 0.0f;
  st.nrm = VEC3(0.0f, 0.0f, 0.0f);
  float dd2 = dot(cd, cd);
  float aa = cd.x * cd.x + cd.y * cd.y; // |C'|^2 sin^2(angle between axis and ray)
  if (!(aa > 1e-14f * dd2)) return st;  // zero tangent, axis parallel to the ray, NaN
  float cdd = c0.x * cd.x + c0.y * cd.y;
  float cxd = c0.x * cd.y - c0.y * cd.x;
  float inv = 1.0f / aa;
  float h = fabs_(cxd) * sqrt(inv); // distance between the ray and the axis line
  float disc = (f.r - h) * (f.r + h);
  float hw = sqrt(max(disc, 0.0f) * dd2 * inv);
  float zeta = -cd.z * cdd * inv + side * hw; // crossing (or closest approach) - c0.z
  float ax = zeta * cd.z - cdd;                   // (X - C(s)) . C'(s)
  st.ok = 1;
  st.real = disc >= 0.0f ? 1 : 0;
  st.z = c0.z + zeta;
  st.g = ax / dd2;
  st.nrm = VEC3(-c0.x, -c0.y, zeta) - st.g * cd;
  return st;
}

// The paper's chain: steps clamped to 0.5; on a sign change regula falsi between the
// last two iterates, bisection every 4th iteration; stops when s leaves [0,1]. (Stops
// also when it converges on a miss, which the paper lets run to the limit: same result.)
FN CurveRoot curve_chain_fast(CurveFrame f, float s0, float side) {
  CurveRoot rt = curve_root_none(s0);
  float s = s0;
  float sold = s0;
  float g1 = 0.0f;
  float g2 = 0.0f;
  for (int k = 0; k < MASQ_CURVE_ITERS; ++k) {
    CurveStep st = curve_step(f, s, side);
    if (st.ok == 0) break;
    if (fabs_(st.g) < MASQ_CURVE_FAST_TOL) {
      if (st.real != 0) {
        rt.found = 1;
        rt.z = st.z;
        rt.s = s;
        rt.nrm = st.nrm;
      }
      break;
    }
    g1 = g2;
    g2 = min(max(st.g, -0.5f), 0.5f);
    float sn = s + g2;
    if (g1 * g2 < 0.0f) sn = (k & 3) == 0 ? 0.5f * (sold + s) : (g2 * sold - g1 * s) / (g2 - g1);
    sold = s;
    s = sn;
    if (s < 0.0f || s > 1.0f) break;
  }
  return rt;
}

KERNEL_NS_END
#endif
