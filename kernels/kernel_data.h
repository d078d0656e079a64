// The scene arrays every kernel reads. GLSL: global SSBOs at the fixed bindings below
// (the Vulkan backends bind by these same macros). OpenCL and C++: one
// struct of pointers passed through the functions as `kd` (see KD_PARAM in shim.h).
#ifndef MASQ_KERNEL_DATA_H
#define MASQ_KERNEL_DATA_H
#include "layout.h"

#define MASQ_BINDING_NODES 0
#define MASQ_BINDING_REFS 1
#define MASQ_BINDING_INSTANCES 2
#define MASQ_BINDING_FRAMES 3
#define MASQ_BINDING_GEOMS 4
#define MASQ_BINDING_TRIANGLES 5
#define MASQ_BINDING_CAPSULES 6
#define MASQ_BINDING_RAYS 7
#define MASQ_BINDING_HITS 8
#define MASQ_BINDING_STATS 9
#define MASQ_BINDING_CONES 10
#define MASQ_BINDING_SPHERES 11
#define MASQ_BINDING_CURVES 12
#define MASQ_BINDING_COUNT 13
// The binary bounding-volume hierarchies (kernels/bv_traverse.h) add two arrays; their
// kernels use bindings 0..MASQ_BV_BINDING_COUNT-1 (0 and 1, the wide BVH, stay unused).
#define MASQ_BINDING_BV_NODES 13
#define MASQ_BINDING_BV_PRIMS 14
#define MASQ_BV_BINDING_COUNT 15

#if defined(MASQ_LANG_GLSL)
layout(std430, binding = MASQ_BINDING_NODES) readonly buffer NodesBuf { WideNode nodes[]; };
layout(std430, binding = MASQ_BINDING_NODES) readonly buffer NodeWordsBuf { uint node_words[]; }; // w8, q8 alias
layout(std430, binding = MASQ_BINDING_REFS) readonly buffer RefsBuf { int refs[]; };
layout(std430, binding = MASQ_BINDING_INSTANCES) readonly buffer InstancesBuf { Instance instances[]; };
layout(std430, binding = MASQ_BINDING_FRAMES) readonly buffer FramesBuf { Frame frames[]; };
layout(std430, binding = MASQ_BINDING_GEOMS) readonly buffer GeomsBuf { Geometry geoms[]; };
layout(std430, binding = MASQ_BINDING_TRIANGLES) readonly buffer TrianglesBuf { Triangle triangles[]; };
layout(std430, binding = MASQ_BINDING_CAPSULES) readonly buffer CapsulesBuf { Capsule capsules[]; };
layout(std430, binding = MASQ_BINDING_CONES) readonly buffer ConesBuf { RoundCone cones[]; };
layout(std430, binding = MASQ_BINDING_SPHERES) readonly buffer SpheresBuf { Sphere spheres[]; };
layout(std430, binding = MASQ_BINDING_CURVES) readonly buffer CurvesBuf { Curve curves[]; };
#else
#if defined(MASQ_LANG_OPENCL)
#define MASQ_GLOBAL __global
#else
#define MASQ_GLOBAL
#endif
LAYOUT_NS_BEGIN
STRUCT_BEGIN(KernelData)
  MASQ_GLOBAL const WideNode* nodes;
  MASQ_GLOBAL const uint* node_words; // the same array as words (node formats w8, q8)
  MASQ_GLOBAL const int* refs;
  MASQ_GLOBAL const Instance* instances;
  MASQ_GLOBAL const Frame* frames;
  MASQ_GLOBAL const Geometry* geoms;
  MASQ_GLOBAL const Triangle* triangles;
  MASQ_GLOBAL const Capsule* capsules;
  MASQ_GLOBAL const RoundCone* cones;
  MASQ_GLOBAL const Sphere* spheres;
  MASQ_GLOBAL const Curve* curves;
  // Binary hierarchies: the node array of the kernel's MASQ_BV_TYPE, and leaf entries.
  MASQ_GLOBAL const BvNodeAabb* bv_aabb;
  MASQ_GLOBAL const BvNodeSphere* bv_sphere;
  MASQ_GLOBAL const BvNodeObb* bv_obb;
  MASQ_GLOBAL const BvNodeScb* bv_scb;
  MASQ_GLOBAL const BvPrimRef* bv_prims;
STRUCT_END(KernelData)
LAYOUT_NS_END
#endif

#endif
