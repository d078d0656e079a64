// The ray-centric frame shared by both curve intersectors (kernels/intersect_curve.h):
// the curve's control points with the ray as the +z axis, de Casteljau evaluation and
// the error-free products that place the frame's origin accurately.
#ifndef MASQ_KERNEL_CURVE_FRAME_H
#define MASQ_KERNEL_CURVE_FRAME_H
#include "prim_hit.h"

// The error-free products below are two_prod_err_ (shim.h): exact on every backend, so
// the accurate dot products give the same bits everywhere (no backend contracts or
// reorders the transforms around them: shim.h, "Contraction").

KERNEL_NS_BEGIN

// The curve in the ray-centric frame: the ray is the +z axis through the origin, z in
// units of length (t = ts + z / |d|).
STRUCT_BEGIN(CurveFrame)
  vec3 b0;
  vec3 b1;
  vec3 b2;
  vec3 b3;
  vec3 t0;    // tangent used at s = 0 (3 * first non-zero control difference)
  vec3 t1;    // tangent used at s = 1
  float r;
  float deg2; // |C'|^2 below this counts as a degenerate (zero) tangent
STRUCT_END(CurveFrame)

STRUCT_BEGIN(CurvePoint)
  vec3 p;
  vec3 d;
  vec3 dd; // second derivative
STRUCT_END(CurvePoint)

// A crossing found by a chain: frame z of the hit, curve parameter, outward normal
// (frame coordinates).
STRUCT_BEGIN(CurveRoot)
  int found;
  float z;
  float s;
  vec3 nrm;
STRUCT_END(CurveRoot)

// No crossing (at curve parameter s): every field set, as every CurveRoot is before a
// path may read it (no undefined value may reach a kernel's decisions: docs/kernels.md).
FN CurveRoot curve_root_none(float s) {
  CurveRoot rt;
  rt.found = 0;
  rt.z = 0.0f;
  rt.s = s;
  rt.nrm = VEC3(0.0f, 0.0f, 0.0f);
  return rt;
}

// de Casteljau: point and derivative; a zero derivative (p0 == p1, ...) is replaced by
// the limit direction at the nearer end, so no step divides by zero.
FN CurvePoint curve_eval(CurveFrame f, float s) {
  float s1 = 1.0f - s;
  vec3 a = s1 * f.b0 + s * f.b1;
  vec3 b = s1 * f.b1 + s * f.b2;
  vec3 c = s1 * f.b2 + s * f.b3;
  vec3 ab = s1 * a + s * b;
  vec3 bc = s1 * b + s * c;
  CurvePoint e;
  e.p = s1 * ab + s * bc;
  e.d = 3.0f * (bc - ab);
  e.dd = 6.0f * ((c - b) - (b - a));
  if (!(dot(e.d, e.d) > f.deg2)) e.d = s < 0.5f ? f.t0 : f.t1;
  return e;
}



// a*b - c*e as if computed in twice the precision, then rounded (Dot2 of two terms:
// within u |ab - ce| + 4u^2 (|ab| + |ce|)). Built from exact products and TwoSum only,
// not Kahan's fma(a, b, -c*e), which needs a fused fma a GLSL driver may not give (shim.h).
FN float curve_dop(float a, float b, float c, float e) {
  float p = a * b;
  float q = -(c * e);
  float s = p + q;
  float z = s - p;
  return s + (((p - (s - z)) + (q - z)) + (two_prod_err_(a, b, p) - two_prod_err_(c, e, -q)));
}

// dot(a, b) computed as if in twice the precision, then rounded (Ogita, Rump and
// Oishi's Dot2: error-free products (two_prod_err_), sums by TwoSum).
FN float curve_dot_acc(vec3 a, vec3 b) {
  float p = a.x * b.x;
  float cmp = two_prod_err_(a.x, b.x, p);
  float h = a.y * b.y;
  float hq = two_prod_err_(a.y, b.y, h);
  float x = p + h;
  float zz = x - p;
  cmp += ((p - (x - zz)) + (h - zz)) + hq;
  float g = a.z * b.z;
  float gq = two_prod_err_(a.z, b.z, g);
  float y = x + g;
  float zy = y - x;
  cmp += ((x - (y - zy)) + (g - zy)) + gq;
  return y + cmp;
}

FN vec3 curve_cross_acc(vec3 a, vec3 b) {
  return VEC3(curve_dop(a.y, b.z, a.z, b.y), curve_dop(a.z, b.x, a.x, b.z), curve_dop(a.x, b.y, a.y, b.x));
}

FN vec3 curve_to_frame(vec3 w, vec3 ex, vec3 ey, vec3 ez) { return VEC3(dot(w, ex), dot(w, ey), dot(w, ez)); }

KERNEL_NS_END
#endif
