// Small helpers shared by the intersectors and the traversal.
#ifndef MASQ_KERNEL_MATH_H
#define MASQ_KERNEL_MATH_H
#include "layout.h"

// Unit roundoff and the gamma_n bounds of Higham (n*u/(1-n*u)), used to pad box tests
// so that fp32 rounding can never cull a ray the intersector would hit.
#define MASQ_U 5.9604645e-8f
#define MASQ_GAMMA3 1.7881397e-7f
#define MASQ_GAMMA4 2.3841864e-7f
// Slab-test interval widening. Ize 2013 needs 1 + 2*gamma_3 with correctly rounded
// division; Vulkan allows 2.5 ulp for division, so twice that is used everywhere.
#define MASQ_BOX_WIDEN (4.0f * MASQ_GAMMA3)

#define V3(arr) VEC3((arr)[0], (arr)[1], (arr)[2])

KERNEL_NS_BEGIN

FN float vcomp(vec3 v, int k) { return k == 0 ? v.x : (k == 1 ? v.y : v.z); }

FN float vmax3_(float a, float b, float c) { return max(a, max(b, c)); }
FN float vmin3_(float a, float b, float c) { return min(a, min(b, c)); }

// 1/d with zero components replaced by a huge finite value, so slab distances never
// become 0*inf = NaN (origin exactly on a slab plane then counts as inside).
FN float safe_rcp(float d) { return d != 0.0f ? 1.0f / d : 1e30f; }
FN vec3 safe_rcp3(vec3 d) { return VEC3(safe_rcp(d.x), safe_rcp(d.y), safe_rcp(d.z)); }

// Row-major 3x4 affine map (rows r0..r2, translation t) applied in a fixed order so the
// error bound in docs/robustness.md holds on every backend.
STRUCT_BEGIN(Affine)
  vec3 r0;
  vec3 r1;
  vec3 r2;
  vec3 t;
STRUCT_END(Affine)

FN Affine affine_from_instance(Instance inst) {
  Affine m;
  m.r0 = VEC3(inst.world_to_object[0], inst.world_to_object[1], inst.world_to_object[2]);
  m.r1 = VEC3(inst.world_to_object[4], inst.world_to_object[5], inst.world_to_object[6]);
  m.r2 = VEC3(inst.world_to_object[8], inst.world_to_object[9], inst.world_to_object[10]);
  m.t = VEC3(inst.world_to_object[3], inst.world_to_object[7], inst.world_to_object[11]);
  return m;
}

FN Affine affine_from_frame(Frame f) {
  Affine m;
  m.r0 = VEC3(f.world_to_object[0], f.world_to_object[1], f.world_to_object[2]);
  m.r1 = VEC3(f.world_to_object[4], f.world_to_object[5], f.world_to_object[6]);
  m.r2 = VEC3(f.world_to_object[8], f.world_to_object[9], f.world_to_object[10]);
  m.t = VEC3(f.world_to_object[3], f.world_to_object[7], f.world_to_object[11]);
  return m;
}

// The transformed ray decides which instance boxes a ray enters, so every backend must
// round it alike (no contraction anywhere: shim.h) for the same hits and counters.
FN vec3 affine_point(Affine m, vec3 p) {
  return VEC3(dot(m.r0, p) + m.t.x, dot(m.r1, p) + m.t.y, dot(m.r2, p) + m.t.z);
}

FN vec3 affine_vector(Affine m, vec3 v) { return VEC3(dot(m.r0, v), dot(m.r1, v), dot(m.r2, v)); }

// Normals go from object to world space with the transpose of the world-to-object map.
FN vec3 affine_normal_to_world(Affine m, vec3 n) { return m.r0 * n.x + m.r1 * n.y + m.r2 * n.z; }

KERNEL_NS_END
#endif
