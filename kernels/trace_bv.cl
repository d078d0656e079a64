// OpenCL entry of the bv kernels: one work-item traces one ray through a binary
// hierarchy of MASQ_BV_TYPE nodes (-D at build time, as the other switches).
#include "bv_traverse.h"

__kernel void trace_bv(__global const Frame* frames, __global const Geometry* geoms,
                       __global const Triangle* triangles, __global const Capsule* capsules,
                       __global const RoundCone* cones, __global const Sphere* spheres,
                       __global const Curve* curves, __global const BV_NODE_T* bv_nodes,
                       __global const BvPrimRef* bv_prims, __global const Ray* rays, __global Hit* hits,
                       __global RayStats* stats, int ray_count, int node_count) {
  int i = (int)get_global_id(0);
  if (i >= ray_count) return;
  KernelData kd;
  kd.frames = frames;
  kd.geoms = geoms;
  kd.triangles = triangles;
  kd.capsules = capsules;
  kd.cones = cones;
  kd.spheres = spheres;
  kd.curves = curves;
  kd.BV_NODES = bv_nodes;
  kd.bv_prims = bv_prims;
  TraceOut o = trace_bv_closest(kd, rays[i], node_count);
  hits[i] = o.hit;
  if (MASQ_STATS) stats[i] = o.stats;
}
