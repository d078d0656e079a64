// The scene arrays every kernel reads. GLSL: global SSBOs at the fixed bindings below
// (the Vulkan backends bind by these same macros), or buffer references read by device
// address (addressed mode, below). OpenCL and C++: one struct of pointers passed
// through the functions as `kd` (see KD_PARAM in shim.h).
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
// The binary bounding-volume hierarchies (kernels/bv_traverse.h) add two arrays; their
// kernels use bindings 0..MASQ_BV_BINDING_COUNT-1 (0 and 1, the wide BVH, stay unused).
// Ray query uses 13 and 14 for its own arrays (kernels/rayquery.comp).
#define MASQ_BINDING_BV_NODES 13
#define MASQ_BINDING_BV_PRIMS 14
#define MASQ_BV_BINDING_COUNT 15
// Compact masquerade entries and their owners (kernels/layout.h, MasqInstance): after
// the numbers the bv and ray query kernels take, so every kernel keeps its bindings.
#define MASQ_BINDING_MASQ_INSTANCES 15
#define MASQ_BINDING_MASQ_OWNERS 16
#define MASQ_BINDING_COUNT 17 // the trace kernel's bindings: 0..16 (13 and 14 unused there)

// Vulkan, addressed mode (MASQ_KD_ADDRESSES=1, a glslang -D): no array is bound; a
// uniform table holds each array's buffer device address at slot = its binding number,
// so one array is limited by maxMemoryAllocationSize instead of maxStorageBufferRange
// (128 MiB on lavapipe). The host picks this mode only for scenes with an array over
// the binding limit (host/vulkan/trace_dispatch.h, docs/kernels.md).
#define MASQ_BINDING_ADDRESSES 20
#define MASQ_ADDRESS_SLOTS 20
#if MASQ_BV_BINDING_COUNT > MASQ_ADDRESS_SLOTS || MASQ_BINDING_COUNT > MASQ_ADDRESS_SLOTS
#error "kernel_data.h: more bindings than address slots"
#endif

#if defined(MASQ_LANG_GLSL)
// MASQ_KD_ARRAY(T, name, binding) declares one scene array read as KD(name)[i]: an SSBO
// at `binding`, or (addressed) a buffer-reference type and its slot. Adding an array is
// one MASQ_KD_ARRAY line (and its binding number above). The _IMPL indirection lets a
// macro (BV_NODES) be the name: arguments next to ## are not expanded.
#if defined(MASQ_KD_ADDRESSES) && MASQ_KD_ADDRESSES
#extension GL_EXT_buffer_reference : require
#extension GL_EXT_buffer_reference_uvec2 : require
layout(std140, binding = MASQ_BINDING_ADDRESSES) uniform KdAddresses { uvec2 kd_address[MASQ_ADDRESS_SLOTS]; };
#define MASQ_KD_ARRAY_IMPL(T, name, b) \
  layout(buffer_reference, std430, buffer_reference_align = 16) readonly buffer name##_ref { T v[]; }; \
  const int name##_slot = b;
#define KD_IMPL(name) name##_ref(kd_address[name##_slot]).v
#define KD(name) KD_IMPL(name)
#else
#define MASQ_KD_ARRAY_IMPL(T, name, b) layout(std430, binding = b) readonly buffer name##_buf { T name[]; };
#define KD(name) name
#endif
#define MASQ_KD_ARRAY(T, name, b) MASQ_KD_ARRAY_IMPL(T, name, b)
MASQ_KD_ARRAY(WideNode, nodes, MASQ_BINDING_NODES)
MASQ_KD_ARRAY(uint, node_words, MASQ_BINDING_NODES) // the same array as words (node formats w8, q8)
MASQ_KD_ARRAY(int, refs, MASQ_BINDING_REFS)
MASQ_KD_ARRAY(Instance, instances, MASQ_BINDING_INSTANCES)
MASQ_KD_ARRAY(MasqInstance, masq_instances, MASQ_BINDING_MASQ_INSTANCES)
MASQ_KD_ARRAY(MasqOwner, masq_owners, MASQ_BINDING_MASQ_OWNERS)
MASQ_KD_ARRAY(Frame, frames, MASQ_BINDING_FRAMES)
MASQ_KD_ARRAY(Geometry, geoms, MASQ_BINDING_GEOMS)
MASQ_KD_ARRAY(Triangle, triangles, MASQ_BINDING_TRIANGLES)
MASQ_KD_ARRAY(Capsule, capsules, MASQ_BINDING_CAPSULES)
MASQ_KD_ARRAY(RoundCone, cones, MASQ_BINDING_CONES)
MASQ_KD_ARRAY(Sphere, spheres, MASQ_BINDING_SPHERES)
MASQ_KD_ARRAY(Curve, curves, MASQ_BINDING_CURVES)
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
  MASQ_GLOBAL const MasqInstance* masq_instances; // compact masquerade entries (TLAS refs < 0)
  MASQ_GLOBAL const MasqOwner* masq_owners;
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
