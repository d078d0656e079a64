// What the stages of the rtpipeline backend's ray-tracing pipeline share (GLSL only;
// VK_KHR_ray_tracing_pipeline, the mechanism of the masquerade paper's OptiX programs):
//   rtpipeline.rgen            one invocation per ray: traceRayEXT into one TLAS part
//   rtpipeline.rint            a procedural primitive's intersection shader: the SAME
//                              intersector as every backend (intersect_primitive)
//   rtpipeline.rchit           the closest procedural hit into the payload
//   rtpipeline_triangle.rahit  robust mode: masq's watertight intersector decides each
//                              triangle candidate (fast mode: opaque, never called)
//   rtpipeline_triangle.rchit  the closest triangle hit into the payload
//   rtpipeline.rmiss           nothing: the payload keeps "no hit"
// Hit groups: one per primitive type (host/vulkan/rt_pipeline.h, kHitGroups). The host
// specialises each intersection stage with only its own type's MASQ_HAVE_* switch on,
// so each group's intersector is that type's alone, as the paper's per-type programs.
// Hit records (the SBT's hit region): one per BLAS, then one per primitive type for
// masquerade instances (host/vulkan/rayquery_plan.h, sbt_record_offset); each record's
// data is its BLAS id (RtRecord), which maps the driver's primitive index to masq's
// through prim_map as in rayquery.comp.
// The host traces the TLAS parts in turn, one launch each; a later part reads the hit of
// the earlier ones from `hits` and looks only nearer (params.part, params.first).
#ifndef MASQ_KERNEL_RT_SHARED_H
#define MASQ_KERNEL_RT_SHARED_H
#include "traverse.h"

// Push constants (the size of kernel::TraceParams): rays in this launch, the first TLAS
// entry of the part traced (its instance records start there), the launch's first ray in
// the ray buffer, and the part's index.
layout(push_constant) uniform RtParams {
  int ray_count;
  int first;
  int ray_offset;
  int part;
} params;

MASQ_KD_ARRAY(int, prim_map, MASQ_BINDING_PRIM_MAP)

// Driver primitive index -> masq's primitive id within BLAS `blas` (see rayquery.comp).
int mapped_prim(int blas, int driver_index) { return KD(prim_map)[KD(prim_map)[blas] + driver_index]; }

// The hit attributes a procedural primitive reports (host: kRtHitAttributeBytes).
struct RtAttribs {
  float nx;
  float ny;
  float nz;
  float u;
  float v;
  int prim;
};

#ifdef MASQ_RT_HIT_STAGE
// The hit record's data after its group handle (host: kRtRecordDataBytes): the BLAS id
// (-1 in a masquerade record).
layout(shaderRecordEXT, std430) buffer RtRecord {
  int blas;
  int pad0;
  int pad1;
  int pad2;
} record;

// The instance record of the TLAS entry hit (one per entry, in submission order).
Instance rt_instance() { return KD(instances)[params.first + int(gl_InstanceCustomIndexEXT)]; }

// Per-ray counters: the stages that call an intersector add to isect_calls (zeroed by
// the host before the first part), so the count is the driver's calls, duplicates
// included (the geometries are built with NO_DUPLICATE_ANY_HIT_INVOCATION).
layout(std430, binding = MASQ_BINDING_STATS) buffer StatsBuf { RayStats stats[]; };
void count_isect_call() {
  if (MASQ_STATS) atomicAdd(stats[params.ray_offset + int(gl_LaunchIDEXT.x)].isect_calls, 1);
}
#endif

#endif
