// Layout check for the GPU-visible structs of kernels/layout.h, in OpenCL C and C++ (a
// test kernel: embedded into test_opencl_layout by tests/CMakeLists.txt, not shipped).
// The field lists below are the single table both sides use: OpenCL C compiles the
// kernels at the end of this file; tests/test_opencl_layout.cpp includes this file as
// C++ (the kernels are then skipped) and compares sizes, offsets and field reads.
// Every field of every struct in layout.h must be listed here (F: scalar, A: array).
#ifndef MASQ_KERNEL_LAYOUT_CHECK_CL
#define MASQ_KERNEL_LAYOUT_CHECK_CL
// kernels/layout.h by a path relative to this file: cmake/embed_opencl.cmake resolves an
// include from the including file's folder only.
#include "../../kernels/layout.h"

#define MASQ_LAYOUT_STRUCTS(S) \
  S(WideNode) S(Instance) S(MasqInstance) S(MasqOwner) S(Frame) S(Geometry) S(Triangle) S(Capsule) S(RoundCone) S(Sphere) S(Curve) S(Ribbon) S(Ray) \
  S(Hit) S(RayStats) S(TraceParams) S(WideNode8) S(QuantNode8) S(BvNodeAabb) S(BvNodeSphere) S(BvNodeObb) S(BvNodeScb) S(BvPrimRef)

#define MASQ_LAYOUT_WideNode(F, A) \
  A(WideNode, lo_x, MASQ_WIDTH) A(WideNode, hi_x, MASQ_WIDTH) A(WideNode, lo_y, MASQ_WIDTH) \
  A(WideNode, hi_y, MASQ_WIDTH) A(WideNode, lo_z, MASQ_WIDTH) A(WideNode, hi_z, MASQ_WIDTH) \
  A(WideNode, child, MASQ_WIDTH) A(WideNode, count, MASQ_WIDTH)
#define MASQ_LAYOUT_WideNode8(F, A) \
  A(WideNode8, lo_x, MASQ_WIDTH8) A(WideNode8, hi_x, MASQ_WIDTH8) A(WideNode8, lo_y, MASQ_WIDTH8) \
  A(WideNode8, hi_y, MASQ_WIDTH8) A(WideNode8, lo_z, MASQ_WIDTH8) A(WideNode8, hi_z, MASQ_WIDTH8) \
  A(WideNode8, child, MASQ_WIDTH8) A(WideNode8, count, MASQ_WIDTH8)
#define MASQ_LAYOUT_QuantNode8(F, A) \
  A(QuantNode8, origin, 3) F(QuantNode8, exps) F(QuantNode8, child_base) F(QuantNode8, ref_base) \
  A(QuantNode8, meta, 2) A(QuantNode8, qlo_x, 2) A(QuantNode8, qhi_x, 2) A(QuantNode8, qlo_y, 2) \
  A(QuantNode8, qhi_y, 2) A(QuantNode8, qlo_z, 2) A(QuantNode8, qhi_z, 2)
#define MASQ_LAYOUT_Instance(F, A) \
  A(Instance, world_to_object, 12) F(Instance, blas_root) F(Instance, geom) F(Instance, prim) F(Instance, scene_inst)
#define MASQ_LAYOUT_MasqInstance(F, A) \
  A(MasqInstance, t, 3) F(MasqInstance, prim) F(MasqInstance, q01) F(MasqInstance, q23) F(MasqInstance, s01) \
  F(MasqInstance, s2_owner)
#define MASQ_LAYOUT_MasqOwner(F, A) F(MasqOwner, geom) F(MasqOwner, scene_inst) A(MasqOwner, pad, 2)
#define MASQ_LAYOUT_Frame(F, A) A(Frame, world_to_object, 12) A(Frame, pad, 4)
#define MASQ_LAYOUT_Geometry(F, A) F(Geometry, type) F(Geometry, first) F(Geometry, count) F(Geometry, pad)
#define MASQ_LAYOUT_Triangle(F, A) A(Triangle, v0, 3) A(Triangle, v1, 3) A(Triangle, v2, 3) A(Triangle, pad, 3)
#define MASQ_LAYOUT_Capsule(F, A) A(Capsule, a, 3) F(Capsule, radius) A(Capsule, b, 3) F(Capsule, pad)
#define MASQ_LAYOUT_RoundCone(F, A) A(RoundCone, a, 3) F(RoundCone, ra) A(RoundCone, b, 3) F(RoundCone, rb)
#define MASQ_LAYOUT_Sphere(F, A) A(Sphere, center, 3) F(Sphere, radius)
#define MASQ_LAYOUT_Curve(F, A) \
  A(Curve, p0, 3) F(Curve, radius) A(Curve, p1, 3) F(Curve, pad1) A(Curve, p2, 3) F(Curve, pad2) A(Curve, p3, 3) \
  F(Curve, pad3)
#define MASQ_LAYOUT_Ribbon(F, A) A(Ribbon, p0, 3) F(Ribbon, r0) A(Ribbon, p1, 3) F(Ribbon, r1) A(Ribbon, n, 3) F(Ribbon, pad)
#define MASQ_LAYOUT_Ray(F, A) A(Ray, org, 3) F(Ray, tmin) A(Ray, dir, 3) F(Ray, tmax)
#define MASQ_LAYOUT_Hit(F, A) \
  F(Hit, t) F(Hit, prim) F(Hit, geom) F(Hit, inst) A(Hit, normal, 3) F(Hit, u) F(Hit, v) F(Hit, fault) F(Hit, fault_node) F(Hit, fault_depth)
#define MASQ_LAYOUT_RayStats(F, A) \
  F(RayStats, tlas_nodes) F(RayStats, blas_nodes) F(RayStats, transforms) F(RayStats, isect_calls)
#define MASQ_LAYOUT_TraceParams(F, A) \
  F(TraceParams, ray_count) F(TraceParams, tlas_root) F(TraceParams, ray_offset) F(TraceParams, step_budget)

#define MASQ_LAYOUT_BvNodeAabb(F, A) A(BvNodeAabb, lo, 3) F(BvNodeAabb, child) A(BvNodeAabb, hi, 3) F(BvNodeAabb, count)
#define MASQ_LAYOUT_BvNodeSphere(F, A) \
  A(BvNodeSphere, center, 3) F(BvNodeSphere, radius) F(BvNodeSphere, child) F(BvNodeSphere, count) A(BvNodeSphere, pad, 2)
#define MASQ_LAYOUT_BvNodeObb(F, A) \
  A(BvNodeObb, axis0, 3) F(BvNodeObb, half0) A(BvNodeObb, axis1, 3) F(BvNodeObb, half1) A(BvNodeObb, axis2, 3) \
  F(BvNodeObb, half2) A(BvNodeObb, center, 3) F(BvNodeObb, child) F(BvNodeObb, count) A(BvNodeObb, pad, 3)
#define MASQ_LAYOUT_BvNodeScb(F, A) \
  A(BvNodeScb, center, 3) F(BvNodeScb, radius) A(BvNodeScb, normal, 3) F(BvNodeScb, e) F(BvNodeScb, f) \
  F(BvNodeScb, child) F(BvNodeScb, count) F(BvNodeScb, pad)
#define MASQ_LAYOUT_BvPrimRef(F, A) F(BvPrimRef, geom) F(BvPrimRef, prim) F(BvPrimRef, scene_inst) F(BvPrimRef, pad)

#if defined(__OPENCL_VERSION__)
// sizes: for each struct in list order, sizeof then the offset of every field; the
// last entry is the number of entries written before it (catches a shorter list).
#define LC_OFFSET_F(T, f) out[k++] = (int)__builtin_offsetof(T, f);
#define LC_OFFSET_A(T, f, n) out[k++] = (int)__builtin_offsetof(T, f);
#define LC_SIZES(T) out[k++] = (int)sizeof(T); MASQ_LAYOUT_##T(LC_OFFSET_F, LC_OFFSET_A)
__kernel void layout_sizes(__global int* out) {
  if (get_global_id(0) != 0) return;
  int k = 0;
  MASQ_LAYOUT_STRUCTS(LC_SIZES)
  out[k] = k;
}

// roundtrip_<T>: reads element i through the struct type, writes every field (array
// elements in order) as raw 4-byte words to flat[i * words + ...], and copies the struct
// back unchanged to out[i]. The host checks both against its own view of the bytes.
#define LC_READ_F(T, f) flat[base + k++] = as_int(v.f);
#define LC_READ_A(T, f, n) for (int j = 0; j < (n); ++j) flat[base + k++] = as_int(v.f[j]);
#define LC_ROUNDTRIP(T) \
  __kernel void roundtrip_##T(__global const T* in, __global T* out, __global int* flat, int count) { \
    int i = (int)get_global_id(0);                                                                   \
    if (i >= count) return;                                                                          \
    T v = in[i];                                                                                     \
    int base = i * (int)(sizeof(T) / 4);                                                             \
    int k = 0;                                                                                       \
    MASQ_LAYOUT_##T(LC_READ_F, LC_READ_A)                                                            \
    out[i] = v;                                                                                      \
  }
MASQ_LAYOUT_STRUCTS(LC_ROUNDTRIP)
#endif

#endif
