// OpenCL entry: one work-item traces one ray (closest hit).
#include "traverse.h"

__kernel void trace(__global const WideNode* nodes, __global const int* refs,
                    __global const Instance* instances, __global const Frame* frames,
                    __global const Geometry* geoms, __global const Triangle* triangles,
                    __global const Capsule* capsules, __global const RoundCone* cones,
                    __global const Sphere* spheres, __global const Curve* curves, __global const Ray* rays, __global Hit* hits,
                    __global RayStats* stats, int ray_count, int tlas_root, int ray_offset,
                    __global const MasqInstance* masq_instances, __global const MasqOwner* masq_owners) {
  int i = (int)get_global_id(0);
  if (i >= ray_count) return;
  KernelData kd;
  kd.nodes = nodes;
  kd.node_words = (__global const uint*)nodes; // node formats w8 and q8 read words
  kd.refs = refs;
  kd.instances = instances;
  kd.masq_instances = masq_instances;
  kd.masq_owners = masq_owners;
  kd.frames = frames;
  kd.geoms = geoms;
  kd.triangles = triangles;
  kd.capsules = capsules;
  kd.cones = cones;
  kd.spheres = spheres;
  kd.curves = curves;
  TraceOut o = trace_closest(kd, rays[ray_offset + i], tlas_root);
  hits[i] = o.hit;
  if (MASQ_STATS) stats[i] = o.stats;
}
