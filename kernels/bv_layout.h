// GPU-visible nodes of the binary bounding-volume hierarchies (AABB, ball, OBB and
// slab-cut-ball trees; docs/bv_hierarchies.md), in the style of layout.h: 4-byte
// scalars only, every struct a multiple of 16 bytes. Every node holds its OWN volume:
// count > 0 is a leaf of `count` primitive references bv_prims[child .. child+count-1];
// count == 0 is an inner node whose two children are the adjacent nodes child and
// child + 1 (one index per node, and both children arrive in one cache line pair).
// Node 0 is the root. The host fits every volume in double and rounds it outward, so
// the fp32 volume contains the exact primitives (bvh/bv/bv_fit.cpp).
#ifndef MASQ_KERNEL_BV_LAYOUT_H
#define MASQ_KERNEL_BV_LAYOUT_H
#include "shim.h"

LAYOUT_NS_BEGIN

// Bounding-volume types (the MASQ_BV_TYPE compile-time switch of the bv kernels).
#define MASQ_BV_AABB 0
#define MASQ_BV_SPHERE 1
#define MASQ_BV_OBB 2
#define MASQ_BV_SCB 3

STRUCT_BEGIN(BvNodeAabb)
  float lo[3];
  int child;
  float hi[3];
  int count;
STRUCT_END(BvNodeAabb)

STRUCT_BEGIN(BvNodeSphere)
  float center[3];
  float radius;
  int child;
  int count;
  int pad[2];
STRUCT_END(BvNodeSphere)

// {x : |dot(axis_k, x - center)| <= half_k, k = 0..2}. The axes are the fp32 values the
// host fitted the half extents to, so they need not be exactly orthonormal.
STRUCT_BEGIN(BvNodeObb)
  float axis0[3];
  float half0;
  float axis1[3];
  float half1;
  float axis2[3];
  float half2;
  float center[3];
  int child;
  int count;
  int pad[3];
STRUCT_END(BvNodeObb)

// Slab cut ball: {x : |x - center| <= radius and f <= dot(normal, x - center) <= e}.
STRUCT_BEGIN(BvNodeScb)
  float center[3];
  float radius;
  float normal[3];
  float e;
  float f;
  int child;
  int count;
  int pad;
STRUCT_END(BvNodeScb)

// A leaf entry: primitive `prim` of geometry `geom`, placed by scene instance (frame)
// `scene_inst`. Hierarchies are built over world-space primitives of every instance.
STRUCT_BEGIN(BvPrimRef)
  int geom;
  int prim;
  int scene_inst;
  int pad;
STRUCT_END(BvPrimRef)

STATIC_ASSERT(sizeof(BvNodeAabb) == 32, bv_node_aabb_size);
STATIC_ASSERT(sizeof(BvNodeSphere) == 32, bv_node_sphere_size);
STATIC_ASSERT(sizeof(BvNodeObb) == 80, bv_node_obb_size);
STATIC_ASSERT(sizeof(BvNodeScb) == 48, bv_node_scb_size);
STATIC_ASSERT(sizeof(BvPrimRef) == 16, bv_prim_ref_size);

LAYOUT_NS_END
#endif
