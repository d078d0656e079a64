// OpenCL entry: one work-item traces one ray (closest hit, or any hit with MASQ_ANY_HIT).
// The scene arrays come first, in the order of kernels/scene_array_table.h.
// Contraction is off for the whole program: kernels/shim.h, "Contraction".
#include "traverse.h"

__kernel void trace(MASQ_CL_SCENE_PARAMS __global const Ray* rays, __global Hit* hits, __global RayStats* stats,
                    TraceParams params) {
  int i = (int)get_global_id(0);
  if (i >= params.ray_count) return;
  MASQ_CL_SET_KERNEL_DATA
  TraceOut o = trace_closest(kd, rays[params.ray_offset + i], params.tlas_root, params.step_budget);
  hits[i] = o.hit;
  if (MASQ_STATS) stats[i] = o.stats;
}
