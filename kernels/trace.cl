// OpenCL entry: one work-item traces one ray (closest hit, or any hit with MASQ_ANY_HIT).
// The scene arrays come first, in the order of kernels/scene_array_table.h.
//
// One contraction policy on every backend (docs/robustness.md, "Float semantics"):
// OpenCL C lets the compiler fuse a*b + c within an expression (FP_CONTRACT defaults
// to ON; PoCL does fuse on FMA hardware), where the cpu (-ffp-contract=off) and Vulkan
// (NoContraction on every operation) round twice. Off for the whole program, before
// any code: only the kernels' explicit fma() fuses.
#pragma OPENCL FP_CONTRACT OFF
#include "traverse.h"

__kernel void trace(MASQ_CL_SCENE_PARAMS __global const Ray* rays, __global Hit* hits, __global RayStats* stats,
                    TraceParams params) {
  int i = (int)get_global_id(0);
  if (i >= params.ray_count) return;
  MASQ_CL_SET_KERNEL_DATA
  TraceOut o = trace_closest(kd, rays[params.ray_offset + i], params.tlas_root);
  hits[i] = o.hit;
  if (MASQ_STATS) stats[i] = o.stats;
}
