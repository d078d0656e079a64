// The ray-centric frame shared by both curve intersectors (kernels/intersect_curve.h):
// the curve's control points with the ray as the +z axis, de Casteljau evaluation and
// the error-free products that place the frame's origin accurately.
#ifndef MASQ_KERNEL_CURVE_FRAME_H
#define MASQ_KERNEL_CURVE_FRAME_H
#include "prim_hit.h"

// A fused multiply-add (error-free products); MASQ_PRECISE (shim.h) keeps GLSL compilers
// from contracting or reordering the error-free transforms. (OpenCL C and C++ neither
// reassociate nor contract without fast-math flags; an unfused fma would only lose
// the extra digits, never give a wrong result.)
#if defined(MASQ_LANG_CPP)
#define MASQ_CURVE_FMA(a, b, c) std::fma((a), (b), (c))
#else
#define MASQ_CURVE_FMA(a, b, c) fma((a), (b), (c))
#endif

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



// a*b - c*e to within 1.5 ulp (Kahan's algorithm with fma).
FN float curve_dop(float a, float b, float c, float e) {
  MASQ_PRECISE float w = c * e;
  MASQ_PRECISE float err = MASQ_CURVE_FMA(-c, e, w);
  MASQ_PRECISE float fa = MASQ_CURVE_FMA(a, b, -w);
  return fa + err;
}

// dot(a, b) computed as if in twice the precision, then rounded (Ogita, Rump and
// Oishi's Dot2: error-free products by fma, sums by TwoSum).
FN float curve_dot_acc(vec3 a, vec3 b) {
  MASQ_PRECISE float p = a.x * b.x;
  MASQ_PRECISE float cmp = MASQ_CURVE_FMA(a.x, b.x, -p);
  MASQ_PRECISE float h = a.y * b.y;
  MASQ_PRECISE float hq = MASQ_CURVE_FMA(a.y, b.y, -h);
  MASQ_PRECISE float x = p + h;
  MASQ_PRECISE float zz = x - p;
  cmp += ((p - (x - zz)) + (h - zz)) + hq;
  MASQ_PRECISE float g = a.z * b.z;
  MASQ_PRECISE float gq = MASQ_CURVE_FMA(a.z, b.z, -g);
  MASQ_PRECISE float y = x + g;
  MASQ_PRECISE float zy = y - x;
  cmp += ((x - (y - zy)) + (g - zy)) + gq;
  return y + cmp;
}

FN vec3 curve_cross_acc(vec3 a, vec3 b) {
  return VEC3(curve_dop(a.y, b.z, a.z, b.y), curve_dop(a.z, b.x, a.x, b.z), curve_dop(a.x, b.y, a.y, b.x));
}

FN vec3 curve_to_frame(vec3 w, vec3 ex, vec3 ey, vec3 ez) { return VEC3(dot(w, ex), dot(w, ey), dot(w, ez)); }

KERNEL_NS_END
#endif
