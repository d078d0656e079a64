// Vulkan compute entry of the bv kernels: one invocation traces one ray through a
// binary hierarchy of MASQ_BV_TYPE nodes (compiled once per type with -D; the other
// switches are specialization constants as in trace.comp). params.tlas_root carries
// the node count.
#version 460
#extension GL_GOOGLE_include_directive : require
layout(local_size_x_id = 3, local_size_y = 1, local_size_z = 1) in;

#include "bv_traverse.h"

layout(std430, binding = MASQ_BINDING_RAYS) readonly buffer RaysBuf { Ray rays[]; };
layout(std430, binding = MASQ_BINDING_HITS) writeonly buffer HitsBuf { Hit hits[]; };
layout(std430, binding = MASQ_BINDING_STATS) writeonly buffer StatsBuf { RayStats stats[]; };
layout(push_constant) uniform PushConstants { TraceParams params; };

void main() {
  int i = int(gl_GlobalInvocationID.x);
  if (i >= params.ray_count) return;
  TraceOut o = trace_bv_closest(rays[params.ray_offset + i], params.tlas_root, params.step_budget);
  hits[i] = o.hit;
  if (MASQ_STATS) stats[i] = o.stats;
}
