// Vulkan ray-query entry: the driver's own acceleration structures find candidates;
// the SAME intersector code as every other backend (intersect_primitive) decides each
// procedural candidate, and the hit record is filled like the compute kernel's
// (hit_from_nearest). One invocation traces one ray (closest hit).
//
// The driver limits a TLAS to maxInstanceCount instances and a BLAS to
// maxPrimitiveCount primitives (2^24-1 on lavapipe), so the host may split the scene
// into several TLAS ("parts", traced one after another: closest hit over all, the
// any-hit query stops at the first) and a geometry into several BLAS.
// The host uploads `instances` in TLAS submission order, one record per TLAS entry
// (a scene instance of a split geometry gets one entry per BLAS part); a candidate's
// record is instances[parts[p].first + custom index], so the 24-bit custom index only
// has to count entries within one part. The record names the geometry and scene
// instance:
//   blas_root >= 0: a BLAS over (a part of) geometry `geom` (triangles: opaque, committed
//     by the driver; capsules: one AABB per capsule, driver primitive index -> capsule id
//     via prim_map), placed with the scene instance's object-to-world transform; the
//     object ray is the driver's.
//   blas_root < 0: masquerade: one unit-box AABB placed on the primitive's OBB; the
//     world ray, moved into scene instance `scene_inst`'s frame, goes to the intersector.
//   prim == MASQ_INST_CLUSTER: a cluster; its BLAS holds the members' local boxes; the
//     world ray goes to the intersector as for masquerade.
// prim_map: entry b (b < number of BLAS) is where BLAS b's primitive ids, in submission
// (BLAS leaf) order, start in prim_map; an instance's SBT record offset is its BLAS b.
// Stats: isect_calls counts intersector calls (triangle tests inside the driver are not
// observable and not counted); node visits and transforms are reported as -1.
#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_ray_query : require
layout(local_size_x_id = 3, local_size_y = 1, local_size_z = 1) in;

#include "traverse.h"

layout(std430, binding = MASQ_BINDING_RAYS) readonly buffer RaysBuf { Ray rays[]; };
layout(std430, binding = MASQ_BINDING_HITS) writeonly buffer HitsBuf { Hit hits[]; };
layout(std430, binding = MASQ_BINDING_STATS) writeonly buffer StatsBuf { RayStats stats[]; };
// One TLAS part: its device address and its first record in `instances`.
struct TlasPart {
  uvec2 tlas;
  int first;
  int pad;
};
layout(std430, binding = MASQ_BINDING_TLAS_PARTS) readonly buffer TlasPartsBuf { TlasPart parts[]; };
MASQ_KD_ARRAY(int, prim_map, MASQ_BINDING_PRIM_MAP)
// TraceParams layout; the second field is the number of TLAS parts (0: no instance).
layout(push_constant) uniform PushConstants { int ray_count; int part_count; int ray_offset; int pad; } params;

int mapped_prim(uint blas, uint driver_index) { return KD(prim_map)[KD(prim_map)[blas] + int(driver_index)]; }

void main() {
  int i = int(gl_GlobalInvocationID.x);
  if (i >= params.ray_count) return;
  Ray ray = rays[params.ray_offset + i];
  vec3 wo = V3(ray.org);
  vec3 wd = V3(ray.dir);
  RayStats st;
  st.tlas_nodes = -1;
  st.blas_nodes = -1;
  st.transforms = -1;
  st.isect_calls = 0;
  Nearest best = nearest_none(ray.tmax);
  // Vulkan requires 0 <= tmin <= tmax and finite values: rays behind the origin
  // (tmin < 0) start at 0 here; infinite tmax becomes the largest float.
  float tmin = max(ray.tmin, 0.0f);
  float tmax = min(ray.tmax, uintBitsToFloat(0x7f7fffffu));
  bool valid = ray_is_valid(wo, wd, ray.tmin, ray.tmax) && tmin <= tmax;
  // Robust mode: triangles are non-opaque, so each triangle candidate comes here and
  // the same watertight intersector as every other backend (with its self-intersection
  // rules) decides it; fast mode lets the driver commit triangles itself.
  uint flags = (MASQ_ROBUST ? gl_RayFlagsNoOpaqueEXT : gl_RayFlagsNoneEXT) |
               (MASQ_ANY_HIT ? gl_RayFlagsTerminateOnFirstHitEXT : gl_RayFlagsNoneEXT);
  // Parts one after another; each later part only looks nearer than the best so far.
  for (int p = 0; valid && p < params.part_count; ++p) {
    if (MASQ_ANY_HIT && best.prim >= 0) break; // occlusion: any hit will do
    int first = parts[p].first;
    float part_tmax = best.prim >= 0 ? min(best.t, tmax) : tmax;
    Nearest gen = nearest_none(ray.tmax); // the last generated (or confirmed) hit
    rayQueryEXT rq;
    rayQueryInitializeEXT(rq, accelerationStructureEXT(parts[p].tlas), flags, 0xFF, wo, tmin, wd, part_tmax);
    while (rayQueryProceedEXT(rq)) {
      uint candidate = rayQueryGetIntersectionTypeEXT(rq, false);
      Instance inst = KD(instances)[first + rayQueryGetIntersectionInstanceCustomIndexEXT(rq, false)];
      float tcur = rayQueryGetIntersectionTypeEXT(rq, true) != gl_RayQueryCommittedIntersectionNoneEXT
                       ? rayQueryGetIntersectionTEXT(rq, true)
                       : part_tmax;
      if (candidate == gl_RayQueryCandidateIntersectionTriangleEXT) {
        int prim = mapped_prim(rayQueryGetIntersectionInstanceShaderBindingTableRecordOffsetEXT(rq, false),
                               rayQueryGetIntersectionPrimitiveIndexEXT(rq, false));
        if (MASQ_STATS) st.isect_calls = st.isect_calls + 1;
        PrimHit ph = intersect_primitive(KD(geoms)[inst.geom], prim,
                                         rayQueryGetIntersectionObjectRayOriginEXT(rq, false),
                                         rayQueryGetIntersectionObjectRayDirectionEXT(rq, false), tmin, tcur);
        if (ph.hit != 0 && (gen.prim < 0 || ph.t <= gen.t)) {
          rayQueryConfirmIntersectionEXT(rq);
          gen.t = ph.t;
          gen.prim = prim;
          gen.geom = inst.geom;
          gen.inst = inst.scene_inst;
          gen.normal = ph.normal;
          gen.u = ph.u;
          gen.v = ph.v;
          if (MASQ_ANY_HIT) rayQueryTerminateEXT(rq);
        }
        continue;
      }
      if (candidate != gl_RayQueryCandidateIntersectionAABBEXT) continue;
      int prim;
      vec3 o;
      vec3 d;
      if (inst.prim == MASQ_INST_CLUSTER) {
        // Cluster: the driver tested the member's local box; the world ray, in the
        // scene instance's frame, goes to the intersector (as for masquerade).
        prim = mapped_prim(rayQueryGetIntersectionInstanceShaderBindingTableRecordOffsetEXT(rq, false),
                           rayQueryGetIntersectionPrimitiveIndexEXT(rq, false));
        Affine f = affine_from_frame(KD(frames)[inst.scene_inst]);
        o = affine_point(f, wo);
        d = affine_vector(f, wd);
      } else if (inst.blas_root < 0) {
        prim = inst.prim;
        Affine f = affine_from_frame(KD(frames)[inst.scene_inst]);
        o = affine_point(f, wo);
        d = affine_vector(f, wd);
      } else {
        prim = mapped_prim(rayQueryGetIntersectionInstanceShaderBindingTableRecordOffsetEXT(rq, false),
                           rayQueryGetIntersectionPrimitiveIndexEXT(rq, false));
        o = rayQueryGetIntersectionObjectRayOriginEXT(rq, false);
        d = rayQueryGetIntersectionObjectRayDirectionEXT(rq, false);
      }
      if (MASQ_STATS) st.isect_calls = st.isect_calls + 1;
      PrimHit ph = intersect_primitive(KD(geoms)[inst.geom], prim, o, d, tmin, tcur);
      if (ph.hit != 0 && ph.t >= tmin && ph.t <= tcur) {
        rayQueryGenerateIntersectionEXT(rq, ph.t);
        gen.t = ph.t;
        gen.prim = prim;
        gen.geom = inst.geom;
        gen.inst = inst.scene_inst;
        gen.normal = ph.normal;
        gen.u = ph.u;
        gen.v = ph.v;
        if (MASQ_ANY_HIT) rayQueryTerminateEXT(rq);
      }
    }
    uint committed = rayQueryGetIntersectionTypeEXT(rq, true);
    if (committed == gl_RayQueryCommittedIntersectionGeneratedEXT) {
      best = gen;
    } else if (committed == gl_RayQueryCommittedIntersectionTriangleEXT && MASQ_ROBUST) {
      best = gen; // confirmed in the loop by our own intersector
    } else if (committed == gl_RayQueryCommittedIntersectionTriangleEXT) {
      Instance inst = KD(instances)[first + rayQueryGetIntersectionInstanceCustomIndexEXT(rq, true)];
      int prim = mapped_prim(rayQueryGetIntersectionInstanceShaderBindingTableRecordOffsetEXT(rq, true),
                             rayQueryGetIntersectionPrimitiveIndexEXT(rq, true));
      Triangle tri = KD(triangles)[KD(geoms)[inst.geom].first + prim];
      vec2 bary = rayQueryGetIntersectionBarycentricsEXT(rq, true);
      best.t = rayQueryGetIntersectionTEXT(rq, true);
      best.prim = prim;
      best.geom = inst.geom;
      best.inst = inst.scene_inst;
      best.normal = cross(V3(tri.v1) - V3(tri.v0), V3(tri.v2) - V3(tri.v0));
      best.u = bary.x;
      best.v = bary.y;
    }
  }
  hits[i] = hit_from_nearest(best);
  if (MASQ_STATS) stats[i] = st;
}
