// How each language reads the scene arrays of kernels/scene_array_table.h. GLSL: global
// SSBOs at each row's binding, or buffer references read by device address (addressed
// mode, below). OpenCL and C++: one struct of pointers passed through the functions as
// `kd` (see KD_PARAM in shim.h), filled from the OpenCL kernel's parameters
// (MASQ_CL_SCENE_PARAMS) or by the cpu backend (host/scene_arrays.h).
#ifndef MASQ_KERNEL_DATA_H
#define MASQ_KERNEL_DATA_H
#include "layout.h"
#include "scene_array_table.h"

// Bindings besides the scene arrays (the table's rows keep clear of these numbers):
// the per-ray buffers of every Vulkan kernel, ray query's own arrays
// (kernels/rayquery.comp) and the address table of addressed mode.
#define MASQ_BINDING_RAYS 7
#define MASQ_BINDING_HITS 8
#define MASQ_BINDING_STATS 9
#define MASQ_BINDING_TLAS_PARTS 20
#define MASQ_BINDING_PRIM_MAP 21

// Vulkan, addressed mode (MASQ_KD_ADDRESSES=1, a glslang -D): no array is bound; a
// uniform table holds each array's buffer device address at slot = its binding number,
// so one array is limited by maxMemoryAllocationSize instead of maxStorageBufferRange
// (128 MiB on lavapipe). The host picks this mode only for scenes with an array over
// the binding limit (host/vulkan/trace_dispatch.h, docs/kernels.md). Every binding
// below MASQ_ADDRESS_SLOTS may be addressed; the table itself comes after them. 22 holds
// ribbons; 23 is free: room for one more scene array before the table moves.
#define MASQ_ADDRESS_SLOTS 24
#define MASQ_BINDING_ADDRESSES MASQ_ADDRESS_SLOTS

#if defined(MASQ_LANG_GLSL)
// MASQ_KD_ARRAY(T, name, binding) declares one array read as KD(name)[i]: an SSBO at
// `binding`, or (addressed) a buffer-reference type and its slot. The scene arrays are
// declared from the table below; rayquery.comp declares its primitive id map the same
// way. The _IMPL indirection lets a macro be the name: arguments next to ## are not
// expanded.
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

#define MASQ_KD_BINDING_OF(T, name, b, kernels, source) const int masq_binding_##name = b;
#define MASQ_KD_DECLARE(T, name, b, kernels, source) MASQ_KD_ARRAY(T, name, b)
#define MASQ_KD_DECLARE_VIEW(T, name, of) MASQ_KD_ARRAY(T, name, masq_binding_##of)
MASQ_SCENE_ARRAYS(MASQ_KD_BINDING_OF)
MASQ_SCENE_ARRAYS(MASQ_KD_DECLARE)
MASQ_SCENE_ARRAY_VIEWS(MASQ_KD_DECLARE_VIEW)

#else
#if defined(MASQ_LANG_OPENCL)
#define MASQ_GLOBAL __global
#else
#define MASQ_GLOBAL
#endif
LAYOUT_NS_BEGIN
#define MASQ_KD_FIELD(T, name, b, kernels, source) MASQ_GLOBAL const T* name;
#define MASQ_KD_VIEW_FIELD(T, name, of) MASQ_GLOBAL const T* name;
STRUCT_BEGIN(KernelData)
  MASQ_SCENE_ARRAYS(MASQ_KD_FIELD)
  MASQ_SCENE_ARRAY_VIEWS(MASQ_KD_VIEW_FIELD)
#if defined(MASQ_LANG_CPP)
  // Not scene data but the cpu's copy of it: each BLAS leaf's capsules in leaf order, at
  // the index of their references, as seven rows of floats (ax ay az bx by bz radius),
  // row k at leaf_capsule_rows + k * leaf_capsule_stride (host/cpu/leaf_capsules.h).
  // Outside the table, as no device kernel reads it and no backend but the cpu's builds it.
  const float* leaf_capsule_rows;
  int leaf_capsule_stride;
  // The curves of the compact masquerade entries in entry order (host/cpu/entry_curves.h):
  // entry k's curve at entry_curves[k]; null where the scene has no curves.
  const Curve* entry_curves;
  // 1 where the TLAS holds compact masquerade entries alone (no Instance), of capsules
  // and curves: its walk may take camera rays in packets (kernels/packet_walk_cpp.h).
  int entry_packets;
#endif
STRUCT_END(KernelData)
LAYOUT_NS_END
#endif

#if defined(MASQ_LANG_OPENCL)
// The OpenCL kernels take every scene array as a parameter, in table order, before their
// own (the host sets them in the same order, host/opencl/cl_scene_buffers.h), and set up
// `kd` from them with MASQ_CL_SET_KERNEL_DATA.
#define MASQ_CL_PARAM(T, name, b, kernels, source) __global const T* name,
#define MASQ_CL_SCENE_PARAMS MASQ_SCENE_ARRAYS(MASQ_CL_PARAM)
#define MASQ_CL_KD_SET(T, name, b, kernels, source) kd.name = name;
#define MASQ_CL_KD_SET_VIEW(T, name, of) kd.name = (__global const T*)kd.of;
#define MASQ_CL_SET_KERNEL_DATA \
  KernelData kd;                \
  MASQ_SCENE_ARRAYS(MASQ_CL_KD_SET) MASQ_SCENE_ARRAY_VIEWS(MASQ_CL_KD_SET_VIEW)
#endif

#endif
