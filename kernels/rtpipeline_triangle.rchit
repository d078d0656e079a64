// rtpipeline: the closest triangle hit. Fast mode: the driver's own (opaque triangles;
// its t and barycentrics, the geometric normal). Robust mode: the any-hit stage has put
// masq's own hit in the payload already.
#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_ray_tracing : require
#define MASQ_RT_HIT_STAGE
#include "rt_shared.h"

hitAttributeEXT vec2 barycentrics;
layout(location = 0) rayPayloadInEXT Nearest payload;

void main() {
  if (MASQ_ROBUST) return;
  Instance inst = rt_instance();
  int prim = mapped_prim(record.blas, gl_PrimitiveID);
  Triangle tri = KD(triangles)[KD(geoms)[inst.geom].first + prim];
  payload.t = gl_HitTEXT;
  payload.prim = prim;
  payload.geom = inst.geom;
  payload.inst = inst.scene_inst;
  payload.normal = cross(V3(tri.v1) - V3(tri.v0), V3(tri.v2) - V3(tri.v0));
  payload.u = barycentrics.x;
  payload.v = barycentrics.y;
}
