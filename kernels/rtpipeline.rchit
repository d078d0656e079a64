// rtpipeline: the closest procedural hit, as its intersection shader reported it.
#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_ray_tracing : require
#define MASQ_RT_HIT_STAGE
#include "rt_shared.h"

hitAttributeEXT RtAttribs attribs;
layout(location = 0) rayPayloadInEXT Nearest payload;

void main() {
  Instance inst = rt_instance();
  payload.t = gl_HitTEXT;
  payload.prim = attribs.prim;
  payload.geom = inst.geom;
  payload.inst = inst.scene_inst;
  payload.normal = vec3(attribs.nx, attribs.ny, attribs.nz);
  payload.u = attribs.u;
  payload.v = attribs.v;
}
