// GLSL half of the layout test (tests/test_glsl_layout.cpp): proves that std430 puts
// every field of every GPU struct in kernels/layout.h where C++ puts it. A test kernel:
// compiled into test_glsl_layout by tests/CMakeLists.txt (kernel headers through
// masq_add_spirv's -I kernels), not shipped.
// For each struct type T (section k) and element i:
//   struct -> words: load in_T[i] through the struct and write its fields, in
//     declaration order, as 32-bit words to flat_out (the C++ struct's bytes, since
//     every field is a 4-byte scalar and C++ adds no padding);
//   words -> struct: read words from flat_in, assign them field by field into a T and
//     store it to out_T[i].
// Section k of the flat arrays starts at n * (words of sections 0..k-1).
#version 460
#extension GL_GOOGLE_include_directive : require
layout(local_size_x = 64, local_size_y = 1, local_size_z = 1) in;

#include "layout.h"

layout(std430, binding = 0) readonly buffer In0 { WideNode in_nodes[]; };
layout(std430, binding = 1) readonly buffer In1 { Instance in_instances[]; };
layout(std430, binding = 2) readonly buffer In2 { Frame in_frames[]; };
layout(std430, binding = 3) readonly buffer In3 { Geometry in_geoms[]; };
layout(std430, binding = 4) readonly buffer In4 { Triangle in_triangles[]; };
layout(std430, binding = 5) readonly buffer In5 { Capsule in_capsules[]; };
layout(std430, binding = 6) readonly buffer In6 { RoundCone in_round_cones[]; };
layout(std430, binding = 7) readonly buffer In7 { Sphere in_spheres[]; };
layout(std430, binding = 8) readonly buffer In8 { Curve in_curves[]; };
layout(std430, binding = 9) readonly buffer In9 { Ray in_rays[]; };
layout(std430, binding = 10) readonly buffer In10 { Hit in_hits[]; };
layout(std430, binding = 11) readonly buffer In11 { RayStats in_stats[]; };
layout(std430, binding = 12) readonly buffer In12 { TraceParams in_params[]; };
layout(std430, binding = 13) readonly buffer In13 { WideNode8 in_nodes8[]; };
layout(std430, binding = 14) readonly buffer In14 { QuantNode8 in_qnodes[]; };
layout(std430, binding = 15) readonly buffer In15 { MasqInstance in_masq[]; };
layout(std430, binding = 16) readonly buffer In16 { MasqOwner in_owners[]; };
layout(std430, binding = 17) readonly buffer In17 { Ribbon in_ribbons[]; };
layout(std430, binding = 18) writeonly buffer FlatOut { uint flat_out[]; };
layout(std430, binding = 19) readonly buffer FlatIn { uint flat_in[]; };
layout(std430, binding = 20) writeonly buffer Out0 { WideNode out_nodes[]; };
layout(std430, binding = 21) writeonly buffer Out1 { Instance out_instances[]; };
layout(std430, binding = 22) writeonly buffer Out2 { Frame out_frames[]; };
layout(std430, binding = 23) writeonly buffer Out3 { Geometry out_geoms[]; };
layout(std430, binding = 24) writeonly buffer Out4 { Triangle out_triangles[]; };
layout(std430, binding = 25) writeonly buffer Out5 { Capsule out_capsules[]; };
layout(std430, binding = 26) writeonly buffer Out6 { RoundCone out_round_cones[]; };
layout(std430, binding = 27) writeonly buffer Out7 { Sphere out_spheres[]; };
layout(std430, binding = 28) writeonly buffer Out8 { Curve out_curves[]; };
layout(std430, binding = 29) writeonly buffer Out9 { Ray out_rays[]; };
layout(std430, binding = 30) writeonly buffer Out10 { Hit out_hits[]; };
layout(std430, binding = 31) writeonly buffer Out11 { RayStats out_stats[]; };
layout(std430, binding = 32) writeonly buffer Out12 { TraceParams out_params[]; };
layout(std430, binding = 33) writeonly buffer Out13 { WideNode8 out_nodes8[]; };
layout(std430, binding = 34) writeonly buffer Out14 { QuantNode8 out_qnodes[]; };
layout(std430, binding = 35) writeonly buffer Out15 { MasqInstance out_masq[]; };
layout(std430, binding = 36) writeonly buffer Out16 { MasqOwner out_owners[]; };
layout(std430, binding = 37) writeonly buffer Out17 { Ribbon out_ribbons[]; };
layout(push_constant) uniform Params { uint n; } pc;

// Words per struct, and the running start of each section (in units of n).
#define W_NODE 32u
#define W_INST 16u
#define W_FRAME 16u
#define W_GEOM 4u
#define W_TRI 12u
#define W_CAP 8u
#define W_RCONE 8u
#define W_SPHERE 4u
#define W_CURVE 16u
#define W_RAY 8u
#define W_HIT 12u
#define W_STATS 4u
#define W_PARAMS 4u
#define W_NODE8 64u
#define W_QNODE 20u
#define W_MASQ 8u
#define W_OWNER 4u
#define W_RIBBON 12u

uint w; // next flat word
#define PUTF(x) flat_out[w++] = floatBitsToUint(x)
#define PUTI(x) flat_out[w++] = uint(x)
#define GETF uintBitsToFloat(flat_in[w++])
#define GETI int(flat_in[w++])

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= pc.n) return;
  uint base = 0u;
  int j;

  // WideNode
  w = base + i * W_NODE;
  WideNode na = in_nodes[i];
  for (j = 0; j < 4; ++j) PUTF(na.lo_x[j]);
  for (j = 0; j < 4; ++j) PUTF(na.hi_x[j]);
  for (j = 0; j < 4; ++j) PUTF(na.lo_y[j]);
  for (j = 0; j < 4; ++j) PUTF(na.hi_y[j]);
  for (j = 0; j < 4; ++j) PUTF(na.lo_z[j]);
  for (j = 0; j < 4; ++j) PUTF(na.hi_z[j]);
  for (j = 0; j < 4; ++j) PUTI(na.child[j]);
  for (j = 0; j < 4; ++j) PUTI(na.count[j]);
  w = base + i * W_NODE;
  WideNode nb;
  for (j = 0; j < 4; ++j) nb.lo_x[j] = GETF;
  for (j = 0; j < 4; ++j) nb.hi_x[j] = GETF;
  for (j = 0; j < 4; ++j) nb.lo_y[j] = GETF;
  for (j = 0; j < 4; ++j) nb.hi_y[j] = GETF;
  for (j = 0; j < 4; ++j) nb.lo_z[j] = GETF;
  for (j = 0; j < 4; ++j) nb.hi_z[j] = GETF;
  for (j = 0; j < 4; ++j) nb.child[j] = GETI;
  for (j = 0; j < 4; ++j) nb.count[j] = GETI;
  out_nodes[i] = nb;
  base += pc.n * W_NODE;

  // Instance
  w = base + i * W_INST;
  Instance ia = in_instances[i];
  for (j = 0; j < 12; ++j) PUTF(ia.world_to_object[j]);
  PUTI(ia.blas_root);
  PUTI(ia.geom);
  PUTI(ia.prim);
  PUTI(ia.scene_inst);
  w = base + i * W_INST;
  Instance ib;
  for (j = 0; j < 12; ++j) ib.world_to_object[j] = GETF;
  ib.blas_root = GETI;
  ib.geom = GETI;
  ib.prim = GETI;
  ib.scene_inst = GETI;
  out_instances[i] = ib;
  base += pc.n * W_INST;

  // Frame
  w = base + i * W_FRAME;
  Frame fa = in_frames[i];
  for (j = 0; j < 12; ++j) PUTF(fa.world_to_object[j]);
  for (j = 0; j < 4; ++j) PUTF(fa.pad[j]);
  w = base + i * W_FRAME;
  Frame fb;
  for (j = 0; j < 12; ++j) fb.world_to_object[j] = GETF;
  for (j = 0; j < 4; ++j) fb.pad[j] = GETF;
  out_frames[i] = fb;
  base += pc.n * W_FRAME;

  // Geometry
  w = base + i * W_GEOM;
  Geometry ga = in_geoms[i];
  PUTI(ga.type);
  PUTI(ga.first);
  PUTI(ga.count);
  PUTI(ga.pad);
  w = base + i * W_GEOM;
  Geometry gb;
  gb.type = GETI;
  gb.first = GETI;
  gb.count = GETI;
  gb.pad = GETI;
  out_geoms[i] = gb;
  base += pc.n * W_GEOM;

  // Triangle
  w = base + i * W_TRI;
  Triangle ta = in_triangles[i];
  for (j = 0; j < 3; ++j) PUTF(ta.v0[j]);
  for (j = 0; j < 3; ++j) PUTF(ta.v1[j]);
  for (j = 0; j < 3; ++j) PUTF(ta.v2[j]);
  for (j = 0; j < 3; ++j) PUTF(ta.pad[j]);
  w = base + i * W_TRI;
  Triangle tb;
  for (j = 0; j < 3; ++j) tb.v0[j] = GETF;
  for (j = 0; j < 3; ++j) tb.v1[j] = GETF;
  for (j = 0; j < 3; ++j) tb.v2[j] = GETF;
  for (j = 0; j < 3; ++j) tb.pad[j] = GETF;
  out_triangles[i] = tb;
  base += pc.n * W_TRI;

  // Capsule
  w = base + i * W_CAP;
  Capsule ca = in_capsules[i];
  for (j = 0; j < 3; ++j) PUTF(ca.a[j]);
  PUTF(ca.radius);
  for (j = 0; j < 3; ++j) PUTF(ca.b[j]);
  PUTF(ca.pad);
  w = base + i * W_CAP;
  Capsule cb;
  for (j = 0; j < 3; ++j) cb.a[j] = GETF;
  cb.radius = GETF;
  for (j = 0; j < 3; ++j) cb.b[j] = GETF;
  cb.pad = GETF;
  out_capsules[i] = cb;
  base += pc.n * W_CAP;

  // RoundCone
  w = base + i * W_RCONE;
  RoundCone rca = in_round_cones[i];
  for (j = 0; j < 3; ++j) PUTF(rca.a[j]);
  PUTF(rca.ra);
  for (j = 0; j < 3; ++j) PUTF(rca.b[j]);
  PUTF(rca.rb);
  w = base + i * W_RCONE;
  RoundCone rcb;
  for (j = 0; j < 3; ++j) rcb.a[j] = GETF;
  rcb.ra = GETF;
  for (j = 0; j < 3; ++j) rcb.b[j] = GETF;
  rcb.rb = GETF;
  out_round_cones[i] = rcb;
  base += pc.n * W_RCONE;

  // Sphere
  w = base + i * W_SPHERE;
  Sphere spa = in_spheres[i];
  for (j = 0; j < 3; ++j) PUTF(spa.center[j]);
  PUTF(spa.radius);
  w = base + i * W_SPHERE;
  Sphere spb;
  for (j = 0; j < 3; ++j) spb.center[j] = GETF;
  spb.radius = GETF;
  out_spheres[i] = spb;
  base += pc.n * W_SPHERE;

  // Curve
  w = base + i * W_CURVE;
  Curve cva = in_curves[i];
  for (j = 0; j < 3; ++j) PUTF(cva.p0[j]);
  PUTF(cva.radius);
  for (j = 0; j < 3; ++j) PUTF(cva.p1[j]);
  PUTF(cva.pad1);
  for (j = 0; j < 3; ++j) PUTF(cva.p2[j]);
  PUTF(cva.pad2);
  for (j = 0; j < 3; ++j) PUTF(cva.p3[j]);
  PUTF(cva.pad3);
  w = base + i * W_CURVE;
  Curve cvb;
  for (j = 0; j < 3; ++j) cvb.p0[j] = GETF;
  cvb.radius = GETF;
  for (j = 0; j < 3; ++j) cvb.p1[j] = GETF;
  cvb.pad1 = GETF;
  for (j = 0; j < 3; ++j) cvb.p2[j] = GETF;
  cvb.pad2 = GETF;
  for (j = 0; j < 3; ++j) cvb.p3[j] = GETF;
  cvb.pad3 = GETF;
  out_curves[i] = cvb;
  base += pc.n * W_CURVE;

  // Ray
  w = base + i * W_RAY;
  Ray ra = in_rays[i];
  for (j = 0; j < 3; ++j) PUTF(ra.org[j]);
  PUTF(ra.tmin);
  for (j = 0; j < 3; ++j) PUTF(ra.dir[j]);
  PUTF(ra.tmax);
  w = base + i * W_RAY;
  Ray rb;
  for (j = 0; j < 3; ++j) rb.org[j] = GETF;
  rb.tmin = GETF;
  for (j = 0; j < 3; ++j) rb.dir[j] = GETF;
  rb.tmax = GETF;
  out_rays[i] = rb;
  base += pc.n * W_RAY;

  // Hit
  w = base + i * W_HIT;
  Hit ha = in_hits[i];
  PUTF(ha.t);
  PUTI(ha.prim);
  PUTI(ha.geom);
  PUTI(ha.inst);
  for (j = 0; j < 3; ++j) PUTF(ha.normal[j]);
  PUTF(ha.u);
  PUTF(ha.v);
  PUTI(ha.fault);
  PUTI(ha.fault_node);
  PUTI(ha.fault_depth);
  w = base + i * W_HIT;
  Hit hb;
  hb.t = GETF;
  hb.prim = GETI;
  hb.geom = GETI;
  hb.inst = GETI;
  for (j = 0; j < 3; ++j) hb.normal[j] = GETF;
  hb.u = GETF;
  hb.v = GETF;
  hb.fault = GETI;
  hb.fault_node = GETI;
  hb.fault_depth = GETI;
  out_hits[i] = hb;
  base += pc.n * W_HIT;

  // RayStats
  w = base + i * W_STATS;
  RayStats sa = in_stats[i];
  PUTI(sa.tlas_nodes);
  PUTI(sa.blas_nodes);
  PUTI(sa.transforms);
  PUTI(sa.isect_calls);
  w = base + i * W_STATS;
  RayStats sb;
  sb.tlas_nodes = GETI;
  sb.blas_nodes = GETI;
  sb.transforms = GETI;
  sb.isect_calls = GETI;
  out_stats[i] = sb;
  base += pc.n * W_STATS;

  // TraceParams
  w = base + i * W_PARAMS;
  TraceParams pa = in_params[i];
  PUTI(pa.ray_count);
  PUTI(pa.tlas_root);
  PUTI(pa.ray_offset);
  PUTI(pa.step_budget);
  w = base + i * W_PARAMS;
  TraceParams pb;
  pb.ray_count = GETI;
  pb.tlas_root = GETI;
  pb.ray_offset = GETI;
  pb.step_budget = GETI;
  out_params[i] = pb;
  base += pc.n * W_PARAMS;

  // WideNode8
  w = base + i * W_NODE8;
  WideNode8 n8a = in_nodes8[i];
  for (j = 0; j < 8; ++j) PUTF(n8a.lo_x[j]);
  for (j = 0; j < 8; ++j) PUTF(n8a.hi_x[j]);
  for (j = 0; j < 8; ++j) PUTF(n8a.lo_y[j]);
  for (j = 0; j < 8; ++j) PUTF(n8a.hi_y[j]);
  for (j = 0; j < 8; ++j) PUTF(n8a.lo_z[j]);
  for (j = 0; j < 8; ++j) PUTF(n8a.hi_z[j]);
  for (j = 0; j < 8; ++j) PUTI(n8a.child[j]);
  for (j = 0; j < 8; ++j) PUTI(n8a.count[j]);
  w = base + i * W_NODE8;
  WideNode8 n8b;
  for (j = 0; j < 8; ++j) n8b.lo_x[j] = GETF;
  for (j = 0; j < 8; ++j) n8b.hi_x[j] = GETF;
  for (j = 0; j < 8; ++j) n8b.lo_y[j] = GETF;
  for (j = 0; j < 8; ++j) n8b.hi_y[j] = GETF;
  for (j = 0; j < 8; ++j) n8b.lo_z[j] = GETF;
  for (j = 0; j < 8; ++j) n8b.hi_z[j] = GETF;
  for (j = 0; j < 8; ++j) n8b.child[j] = GETI;
  for (j = 0; j < 8; ++j) n8b.count[j] = GETI;
  out_nodes8[i] = n8b;
  base += pc.n * W_NODE8;

  // QuantNode8
  w = base + i * W_QNODE;
  QuantNode8 qa = in_qnodes[i];
  for (j = 0; j < 3; ++j) PUTF(qa.origin[j]);
  PUTI(qa.exps);
  PUTI(qa.child_base);
  PUTI(qa.ref_base);
  for (j = 0; j < 2; ++j) PUTI(qa.meta[j]);
  for (j = 0; j < 2; ++j) PUTI(qa.qlo_x[j]);
  for (j = 0; j < 2; ++j) PUTI(qa.qhi_x[j]);
  for (j = 0; j < 2; ++j) PUTI(qa.qlo_y[j]);
  for (j = 0; j < 2; ++j) PUTI(qa.qhi_y[j]);
  for (j = 0; j < 2; ++j) PUTI(qa.qlo_z[j]);
  for (j = 0; j < 2; ++j) PUTI(qa.qhi_z[j]);
  w = base + i * W_QNODE;
  QuantNode8 qb;
  for (j = 0; j < 3; ++j) qb.origin[j] = GETF;
  qb.exps = flat_in[w++];
  qb.child_base = GETI;
  qb.ref_base = GETI;
  for (j = 0; j < 2; ++j) qb.meta[j] = flat_in[w++];
  for (j = 0; j < 2; ++j) qb.qlo_x[j] = flat_in[w++];
  for (j = 0; j < 2; ++j) qb.qhi_x[j] = flat_in[w++];
  for (j = 0; j < 2; ++j) qb.qlo_y[j] = flat_in[w++];
  for (j = 0; j < 2; ++j) qb.qhi_y[j] = flat_in[w++];
  for (j = 0; j < 2; ++j) qb.qlo_z[j] = flat_in[w++];
  for (j = 0; j < 2; ++j) qb.qhi_z[j] = flat_in[w++];
  out_qnodes[i] = qb;
  base += pc.n * W_QNODE;

  // MasqInstance
  w = base + i * W_MASQ;
  MasqInstance ma = in_masq[i];
  for (j = 0; j < 3; ++j) PUTF(ma.t[j]);
  PUTI(ma.prim);
  PUTI(ma.q01);
  PUTI(ma.q23);
  PUTI(ma.s01);
  PUTI(ma.s2_owner);
  w = base + i * W_MASQ;
  MasqInstance mb;
  for (j = 0; j < 3; ++j) mb.t[j] = GETF;
  mb.prim = GETI;
  mb.q01 = flat_in[w++];
  mb.q23 = flat_in[w++];
  mb.s01 = flat_in[w++];
  mb.s2_owner = flat_in[w++];
  out_masq[i] = mb;
  base += pc.n * W_MASQ;

  // MasqOwner
  w = base + i * W_OWNER;
  MasqOwner oa = in_owners[i];
  PUTI(oa.geom);
  PUTI(oa.scene_inst);
  for (j = 0; j < 2; ++j) PUTI(oa.pad[j]);
  w = base + i * W_OWNER;
  MasqOwner ob;
  ob.geom = GETI;
  ob.scene_inst = GETI;
  for (j = 0; j < 2; ++j) ob.pad[j] = GETI;
  out_owners[i] = ob;
  base += pc.n * W_OWNER;

  // Ribbon
  w = base + i * W_RIBBON;
  Ribbon rba = in_ribbons[i];
  for (j = 0; j < 3; ++j) PUTF(rba.p0[j]);
  PUTF(rba.r0);
  for (j = 0; j < 3; ++j) PUTF(rba.p1[j]);
  PUTF(rba.r1);
  for (j = 0; j < 3; ++j) PUTF(rba.n[j]);
  PUTF(rba.pad);
  w = base + i * W_RIBBON;
  Ribbon rbb;
  for (j = 0; j < 3; ++j) rbb.p0[j] = GETF;
  rbb.r0 = GETF;
  for (j = 0; j < 3; ++j) rbb.p1[j] = GETF;
  rbb.r1 = GETF;
  for (j = 0; j < 3; ++j) rbb.n[j] = GETF;
  rbb.pad = GETF;
  out_ribbons[i] = rbb;
}
