// Vulkan ray-query entry: the driver's own acceleration structures find candidates;
// the SAME intersector code as every other backend (intersect_primitive) decides each
// procedural candidate, and the hit record is filled like the compute kernel's
// (hit_from_nearest). One invocation traces one ray (closest hit).
//
// TLAS instance custom index i = entry i of `instances` (kernels/layout.h), which names
// the geometry and scene instance:
//   blas_root >= 0: a BLAS over geometry `geom` (triangles: opaque, committed by the
//     driver; capsules: one AABB per capsule, driver primitive index -> capsule id via
//     prim_map), placed with the scene instance's object-to-world transform; the object
//     ray is the driver's.
//   blas_root < 0: masquerade: one unit-box AABB placed on the primitive's OBB; the
//     world ray, moved into scene instance `scene_inst`'s frame, goes to the intersector.
//   prim == MASQ_INST_CLUSTER: a cluster; its BLAS holds the members' local boxes, the
//     instance's SBT record offset is where their ids start in prim_map; the world ray
//     goes to the intersector as for masquerade.
// prim_map: entries 0..G-1 are the offsets of each geometry's list of primitive ids in
// submission (BLAS leaf) order.
// Stats: isect_calls counts intersector calls (triangle tests inside the driver are not
// observable and not counted); node visits and transforms are reported as -1.
#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_ray_query : require
layout(local_size_x_id = 3, local_size_y = 1, local_size_z = 1) in;

#include "traverse.h"

#define MASQ_BINDING_TLAS 13
#define MASQ_BINDING_PRIM_MAP 14

layout(std430, binding = MASQ_BINDING_RAYS) readonly buffer RaysBuf { Ray rays[]; };
layout(std430, binding = MASQ_BINDING_HITS) writeonly buffer HitsBuf { Hit hits[]; };
layout(std430, binding = MASQ_BINDING_STATS) writeonly buffer StatsBuf { RayStats stats[]; };
layout(binding = MASQ_BINDING_TLAS) uniform accelerationStructureEXT tlas;
layout(std430, binding = MASQ_BINDING_PRIM_MAP) readonly buffer PrimMapBuf { int prim_map[]; };
// TraceParams layout; the second field says whether the TLAS holds any instance.
layout(push_constant) uniform PushConstants { int ray_count; int has_tlas; int ray_offset; int pad; } params;

int mapped_prim(int geom_id, uint driver_index) { return prim_map[prim_map[geom_id] + int(driver_index)]; }

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
  if (params.has_tlas != 0 && ray_is_valid(wo, wd, ray.tmin, ray.tmax) && tmin <= tmax) {
    Nearest gen = best; // the last generated (procedural) hit
    rayQueryEXT rq;
    // Robust mode: triangles are non-opaque, so each triangle candidate comes here and
    // the same watertight intersector as every other backend (with its self-intersection
    // rules) decides it; fast mode lets the driver commit triangles itself.
    uint flags = (MASQ_ROBUST ? gl_RayFlagsNoOpaqueEXT : gl_RayFlagsNoneEXT) |
                 (MASQ_ANY_HIT ? gl_RayFlagsTerminateOnFirstHitEXT : gl_RayFlagsNoneEXT);
    rayQueryInitializeEXT(rq, tlas, flags, 0xFF, wo, tmin, wd, tmax);
    while (rayQueryProceedEXT(rq)) {
      uint candidate = rayQueryGetIntersectionTypeEXT(rq, false);
      if (candidate == gl_RayQueryCandidateIntersectionTriangleEXT) {
        Instance inst = instances[rayQueryGetIntersectionInstanceCustomIndexEXT(rq, false)];
        int prim = mapped_prim(inst.geom, rayQueryGetIntersectionPrimitiveIndexEXT(rq, false));
        float tcur = rayQueryGetIntersectionTypeEXT(rq, true) != gl_RayQueryCommittedIntersectionNoneEXT
                         ? rayQueryGetIntersectionTEXT(rq, true)
                         : tmax;
        if (MASQ_STATS) st.isect_calls = st.isect_calls + 1;
        PrimHit ph = intersect_primitive(geoms[inst.geom], prim, rayQueryGetIntersectionObjectRayOriginEXT(rq, false),
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
          if (MASQ_ANY_HIT) rayQueryTerminateEXT(rq); // occlusion: any hit will do
        }
        continue;
      }
      if (candidate != gl_RayQueryCandidateIntersectionAABBEXT) continue;
      Instance inst = instances[rayQueryGetIntersectionInstanceCustomIndexEXT(rq, false)];
      int prim;
      vec3 o;
      vec3 d;
      if (inst.prim == MASQ_INST_CLUSTER) {
        // Cluster: the driver tested the member's local box; the world ray, in the
        // scene instance's frame, goes to the intersector (as for masquerade).
        prim = prim_map[int(rayQueryGetIntersectionInstanceShaderBindingTableRecordOffsetEXT(rq, false)) +
                        int(rayQueryGetIntersectionPrimitiveIndexEXT(rq, false))];
        Affine f = affine_from_frame(frames[inst.scene_inst]);
        o = affine_point(f, wo);
        d = affine_vector(f, wd);
      } else if (inst.blas_root < 0) {
        prim = inst.prim;
        Affine f = affine_from_frame(frames[inst.scene_inst]);
        o = affine_point(f, wo);
        d = affine_vector(f, wd);
      } else {
        prim = mapped_prim(inst.geom, rayQueryGetIntersectionPrimitiveIndexEXT(rq, false));
        o = rayQueryGetIntersectionObjectRayOriginEXT(rq, false);
        d = rayQueryGetIntersectionObjectRayDirectionEXT(rq, false);
      }
      float tcur = rayQueryGetIntersectionTypeEXT(rq, true) != gl_RayQueryCommittedIntersectionNoneEXT
                       ? rayQueryGetIntersectionTEXT(rq, true)
                       : tmax;
      if (MASQ_STATS) st.isect_calls = st.isect_calls + 1;
      PrimHit ph = intersect_primitive(geoms[inst.geom], prim, o, d, tmin, tcur);
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
      Instance inst = instances[rayQueryGetIntersectionInstanceCustomIndexEXT(rq, true)];
      int prim = mapped_prim(inst.geom, rayQueryGetIntersectionPrimitiveIndexEXT(rq, true));
      Triangle tri = triangles[geoms[inst.geom].first + prim];
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
