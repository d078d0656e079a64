// Conservative ray/box tests: the 4-wide node test and the masquerade unit-box test
// (the 8-wide formats are in node_formats.h).
#ifndef MASQ_KERNEL_BOX_H
#define MASQ_KERNEL_BOX_H
#include "math.h"
#include "slab_simd_cpp.h"

KERNEL_NS_BEGIN

// Entry distance of each child box, or +inf when the ray misses it within [tmin, tmax],
// with the slot's child and count decoded (the WideNode slot rules) whatever the node
// format. Slots beyond the format's width hold wide_hits_none's values.
STRUCT_BEGIN(WideHits)
  float tnear[MASQ_WIDTH8];
  float tfar[MASQ_WIDTH8];
  int child[MASQ_WIDTH8];
  int count[MASQ_WIDTH8];
STRUCT_END(WideHits)

// Every slot missed and empty (tnear +inf, tfar 0, child -1, count -1). The 4-wide tests
// start from it, so the slots beyond their width hold these values, not undefined ones
// (no undefined value may reach a decision: docs/kernels.md, "Values never undefined").
FN WideHits wide_hits_none() {
  WideHits r;
  for (int i = 0; i < MASQ_WIDTH8; ++i) {
    r.tnear[i] = inf_();
    r.tfar[i] = 0.0f;
    r.child[i] = -1;
    r.count[i] = -1;
  }
  return r;
}

// Widen a slab interval outward by the rounding bound (sign-independent).
FN float widen_lo(float t) { return t - fabs_(t) * MASQ_BOX_WIDEN; }
FN float widen_hi(float t) { return t + fabs_(t) * MASQ_BOX_WIDEN; }

#if defined(MASQ_LANG_CPP)
// cpu: the w4 test, plain or padded, four slots at once (slab_simd_cpp.h).
FN WideHits wide_node_simd(WideNode n, vec3 o, vec3 inv_d, int padded, vec3 pad, float tmin, float tmax) {
  WideHits r = wide_hits_none();
  simd::slab_hits4(n.lo_x, n.hi_x, n.lo_y, n.hi_y, n.lo_z, n.hi_z, n.count, o, inv_d, padded, pad, tmin, tmax,
                   r.tnear, r.tfar);
  for (int i = 0; i < MASQ_WIDTH; ++i) {
    r.child[i] = n.child[i];
    r.count[i] = n.count[i];
  }
  return r;
}
#endif

// The one-source form: GLSL and OpenCL run it (PoCL vectorises across work-items); the
// cpu dialect runs the same operations on four slots at once (slab_simd_cpp.h).
FN WideHits intersect_wide_node_loop(WideNode n, vec3 o, vec3 inv_d, float tmin, float tmax) {
  WideHits r = wide_hits_none();
  for (int i = 0; i < MASQ_WIDTH; ++i) {
    float tx0 = (n.lo_x[i] - o.x) * inv_d.x;
    float tx1 = (n.hi_x[i] - o.x) * inv_d.x;
    float ty0 = (n.lo_y[i] - o.y) * inv_d.y;
    float ty1 = (n.hi_y[i] - o.y) * inv_d.y;
    float tz0 = (n.lo_z[i] - o.z) * inv_d.z;
    float tz1 = (n.hi_z[i] - o.z) * inv_d.z;
    float tn = widen_lo(vmax3_(min(tx0, tx1), min(ty0, ty1), min(tz0, tz1)));
    float tf = widen_hi(vmin3_(max(tx0, tx1), max(ty0, ty1), max(tz0, tz1)));
    bool hit = n.count[i] >= 0 && tn <= tf && tf >= tmin && tn <= tmax;
    r.tnear[i] = hit ? max(tn, tmin) : inf_();
    r.tfar[i] = tf;
    r.child[i] = n.child[i];
    r.count[i] = n.count[i];
  }
  return r;
}

FN WideHits intersect_wide_node(WideNode n, vec3 o, vec3 inv_d, float tmin, float tmax) {
#if defined(MASQ_LANG_CPP)
  return wide_node_simd(n, o, inv_d, 0, vec3(0.0f), tmin, tmax);
#else
  return intersect_wide_node_loop(n, o, inv_d, tmin, tmax);
#endif
}

// Per-axis error bound of the fp32 ray transform o' = A o + b, d' = A d at any t up to
// t_bound (docs/robustness.md), before the bound's own rounding is covered:
//   origin:    gamma_4 * (|A| |o| + |b|)
//   direction: gamma_3 * |A| |d|, times t_bound
// Rounded alike on every backend (no contraction anywhere: shim.h), like the transform
// it bounds: the padded box decides the masquerade's cull.
// In three parts, for a caller that meets one transform at several t_bound (the cpu's o4
// walk, node_formats.h): the origin term, |A| |d|, and their sum at t_bound.
FN vec3 transform_error_origin(Affine m, vec3 wo) {
  vec3 ao = vabs_(wo);
  return VEC3(MASQ_GAMMA4 * (dot(vabs_(m.r0), ao) + fabs_(m.t.x)), MASQ_GAMMA4 * (dot(vabs_(m.r1), ao) + fabs_(m.t.y)),
              MASQ_GAMMA4 * (dot(vabs_(m.r2), ao) + fabs_(m.t.z)));
}
FN vec3 transform_error_dir(Affine m, vec3 wd) {
  vec3 ad = vabs_(wd);
  return VEC3(dot(vabs_(m.r0), ad), dot(vabs_(m.r1), ad), dot(vabs_(m.r2), ad));
}
FN vec3 transform_error_at(vec3 origin_term, vec3 dir_term, float t_bound) {
  float tb = fabs_(t_bound);
  return VEC3(origin_term.x + tb * MASQ_GAMMA3 * dir_term.x, origin_term.y + tb * MASQ_GAMMA3 * dir_term.y,
              origin_term.z + tb * MASQ_GAMMA3 * dir_term.z);
}
FN vec3 transform_error(Affine m, vec3 wo, vec3 wd, float t_bound) {
  return transform_error_at(transform_error_origin(m, wo), transform_error_dir(m, wd), t_bound);
}

// The padding a box in the transformed space needs when the primitives inside are
// intersected with a different (untransformed) ray. The bound itself is evaluated in
// fp32: a few more relative steps cover that.
FN vec3 transform_pad(Affine m, vec3 wo, vec3 wd, float t_bound) {
  return transform_error(m, wo, wd, t_bound) * (1.0f + 8.0f * MASQ_U);
}

// The masquerade's "BLAS": the unit box [-1,1]^3 in the instance's object space, padded
// per axis by the error bound of the fp32 ray transform (transform_error), with t_bound
// the exit distance of the world box that holds the instance (the largest t at which
// the primitive can be hit).
FN bool hit_unit_box_padded(Affine m, vec3 wo, vec3 wd, vec3 oo, vec3 od, float tmin, float tmax,
                            float t_bound) {
  vec3 p = transform_error(m, wo, wd, t_bound);
  // The bounds themselves are rounded outward by one more relative step.
  vec3 ext = VEC3(1.0f + p.x, 1.0f + p.y, 1.0f + p.z) * (1.0f + 2.0f * MASQ_U);
  vec3 inv = safe_rcp3(od);
  float tx0 = (-ext.x - oo.x) * inv.x;
  float tx1 = (ext.x - oo.x) * inv.x;
  float ty0 = (-ext.y - oo.y) * inv.y;
  float ty1 = (ext.y - oo.y) * inv.y;
  float tz0 = (-ext.z - oo.z) * inv.z;
  float tz1 = (ext.z - oo.z) * inv.z;
  float tn = widen_lo(vmax3_(min(tx0, tx1), min(ty0, ty1), min(tz0, tz1)));
  float tf = widen_hi(vmin3_(max(tx0, tx1), max(ty0, ty1), max(tz0, tz1)));
  return tn <= tf && tf >= tmin && tn <= tmax;
}

// The wide node test with every child box grown by pad on each axis (cluster BLAS of
// the robust mode). lo - pad is rounded to nearest, so the bounds also move outward by
// 2u of their magnitude; the slab interval is widened as in intersect_wide_node.
FN WideHits intersect_wide_node_padded_loop(WideNode n, vec3 o, vec3 inv_d, vec3 pad, float tmin, float tmax) {
  WideHits r = wide_hits_none();
  for (int i = 0; i < MASQ_WIDTH; ++i) {
    float tx0 = (n.lo_x[i] - (pad.x + fabs_(n.lo_x[i]) * 2.0f * MASQ_U) - o.x) * inv_d.x;
    float tx1 = (n.hi_x[i] + (pad.x + fabs_(n.hi_x[i]) * 2.0f * MASQ_U) - o.x) * inv_d.x;
    float ty0 = (n.lo_y[i] - (pad.y + fabs_(n.lo_y[i]) * 2.0f * MASQ_U) - o.y) * inv_d.y;
    float ty1 = (n.hi_y[i] + (pad.y + fabs_(n.hi_y[i]) * 2.0f * MASQ_U) - o.y) * inv_d.y;
    float tz0 = (n.lo_z[i] - (pad.z + fabs_(n.lo_z[i]) * 2.0f * MASQ_U) - o.z) * inv_d.z;
    float tz1 = (n.hi_z[i] + (pad.z + fabs_(n.hi_z[i]) * 2.0f * MASQ_U) - o.z) * inv_d.z;
    float tn = widen_lo(vmax3_(min(tx0, tx1), min(ty0, ty1), min(tz0, tz1)));
    float tf = widen_hi(vmin3_(max(tx0, tx1), max(ty0, ty1), max(tz0, tz1)));
    bool hit = n.count[i] >= 0 && tn <= tf && tf >= tmin && tn <= tmax;
    r.tnear[i] = hit ? max(tn, tmin) : inf_();
    r.tfar[i] = tf;
    r.child[i] = n.child[i];
    r.count[i] = n.count[i];
  }
  return r;
}

FN WideHits intersect_wide_node_padded(WideNode n, vec3 o, vec3 inv_d, vec3 pad, float tmin, float tmax) {
#if defined(MASQ_LANG_CPP)
  return wide_node_simd(n, o, inv_d, 1, pad, tmin, tmax);
#else
  return intersect_wide_node_padded_loop(n, o, inv_d, pad, tmin, tmax);
#endif
}

// Fast mode: the plain unit-box test of the transformed ray, as RT hardware does it
// (no padding, no widening; can cull grazing rays the intersector would hit).
FN bool hit_unit_box(vec3 oo, vec3 od, float tmin, float tmax) {
  vec3 inv = safe_rcp3(od);
  float tx0 = (-1.0f - oo.x) * inv.x;
  float tx1 = (1.0f - oo.x) * inv.x;
  float ty0 = (-1.0f - oo.y) * inv.y;
  float ty1 = (1.0f - oo.y) * inv.y;
  float tz0 = (-1.0f - oo.z) * inv.z;
  float tz1 = (1.0f - oo.z) * inv.z;
  float tn = vmax3_(min(tx0, tx1), min(ty0, ty1), min(tz0, tz1));
  float tf = vmin3_(max(tx0, tx1), max(ty0, ty1), max(tz0, tz1));
  return tn <= tf && tf >= tmin && tn <= tmax;
}

KERNEL_NS_END
#endif
