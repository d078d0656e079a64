// Closest-hit traversal of a binary bounding-volume hierarchy over world-space
// primitives (kernels/bv_layout.h), with ONE node volume type per compiled variant:
// MASQ_BV_TYPE = MASQ_BV_AABB | MASQ_BV_SPHERE | MASQ_BV_OBB | MASQ_BV_SCB (a -D
// macro for C++, OpenCL C and GLSL alike, since it picks the node array of
// kernels/scene_array_table.h, its struct type and its volume test).
// The root's volume is tested first; at an inner node both children's volumes are
// tested and the hit ones pushed, nearer (by entry lower bound) on top. Leaves run the
// shared intersectors in their scene instance's frame, as the masquerade path does.
// Counters (MASQ_STATS), in RayStats: blas_nodes = N_b (ray/volume tests),
// isect_calls = N_t (ray/primitive tests), tlas_nodes = nodes popped, transforms = 0.
#ifndef MASQ_KERNEL_BV_TRAVERSE_H
#define MASQ_KERNEL_BV_TRAVERSE_H
#include "bv_tests.h"
#include "traverse.h"

#ifndef MASQ_BV_TYPE
#define MASQ_BV_TYPE MASQ_BV_SCB
#endif
#if MASQ_BV_TYPE == MASQ_BV_AABB
#define BV_NODE_T BvNodeAabb
#define BV_NODES bv_aabb
#define BV_HIT(nd, tmax_) bv_hit_aabb(nd, bray, tmin, tmax_)
#elif MASQ_BV_TYPE == MASQ_BV_SPHERE
#define BV_NODE_T BvNodeSphere
#define BV_NODES bv_sphere
#define BV_HIT(nd, tmax_) bv_hit_sphere(nd, bray, tmin, tmax_)
#elif MASQ_BV_TYPE == MASQ_BV_OBB
#define BV_NODE_T BvNodeObb
#define BV_NODES bv_obb
#define BV_HIT(nd, tmax_) bv_hit_obb(nd, bray, tmin, tmax_)
#else
#define BV_NODE_T BvNodeScb
#define BV_NODES bv_scb
#define BV_HIT(nd, tmax_) bv_hit_scb(nd, bray, tmin, tmax_)
#endif

KERNEL_NS_BEGIN

// node_count == 0: an empty hierarchy (every ray misses). budget: the most loop steps
// the walk may take (TraceParams::step_budget, the node count); a walk past it, or a push
// onto a full stack, stops the ray with its fault set (MASQ_STEP_CHECK; layout.h, Hit).
FN TraceOut trace_bv_closest(KD_PARAM Ray ray, int node_count, int budget) {
  TraceOut res;
  res.stats.tlas_nodes = 0;
  res.stats.blas_nodes = 0;
  res.stats.transforms = 0;
  res.stats.isect_calls = 0;
  vec3 o = V3(ray.org);
  vec3 d = V3(ray.dir);
  float tmin = ray.tmin;
  Nearest best = nearest_none(ray.tmax);
  if (node_count <= 0 || !ray_is_valid(o, d, tmin, ray.tmax)) {
    res.hit = hit_from_nearest(KD_ARG best);
    return res;
  }
  BvRay bray = bv_ray(o, d);
  int stack_node[MASQ_STACK_DIM(MASQ_BLAS_STACK)];
  float stack_t[MASQ_STACK_DIM(MASQ_BLAS_STACK)];
  int sp = 0;
  float troot = BV_HIT(KD(BV_NODES)[0], best.t);
  if (MASQ_STATS) res.stats.blas_nodes = 1;
  if (troot != inf_()) {
    stack_node[0] = 0;
    stack_t[0] = troot;
    sp = 1;
  }
  int steps = 0;
  int fault = 0;
  int fault_node = 0;
  while (sp > 0) {
    sp = sp - 1;
    int node = stack_node[sp];
    if (MASQ_STEP_CHECK) {
      if (steps >= budget) {
        fault = MASQ_FAULT_STEP_BUDGET | (MASQ_LEVEL_BV << 8);
        fault_node = node;
        break;
      }
      steps = steps + 1;
    }
    if (stack_t[sp] > best.t) continue;
    BV_NODE_T nd = KD(BV_NODES)[node];
    if (MASQ_STATS) res.stats.tlas_nodes = res.stats.tlas_nodes + 1;
    if (nd.count > 0) {
      for (int j = 0; j < nd.count; ++j) {
        BvPrimRef pr = KD(bv_prims)[nd.child + j];
        Affine f = affine_from_frame(KD(frames)[pr.scene_inst]);
        Geometry g = KD(geoms)[pr.geom];
        if (MASQ_STATS) res.stats.isect_calls = res.stats.isect_calls + 1;
        PrimHit ph = intersect_primitive(KD_ARG g, pr.prim, affine_point(f, o), affine_vector(f, d), tmin, best.t);
        best = nearest_take(best, ph, pr.prim, pr.geom, pr.scene_inst);
      }
      continue;
    }
    float tl = BV_HIT(KD(BV_NODES)[nd.child], best.t);
    float tr = BV_HIT(KD(BV_NODES)[nd.child + 1], best.t);
    if (MASQ_STATS) res.stats.blas_nodes = res.stats.blas_nodes + 2;
    // Farther first, so the nearer child is popped next. The stack holds the tree's
    // depth (bvh/bv/bv_scene.cpp sets the need); a push beyond it is a fault.
    bool left_first = tl <= tr;
    int near_i = left_first ? nd.child : nd.child + 1;
    int far_i = left_first ? nd.child + 1 : nd.child;
    float near_t = left_first ? tl : tr;
    float far_t = left_first ? tr : tl;
    int pushes = (far_t != inf_() ? 1 : 0) + (near_t != inf_() ? 1 : 0);
    if (sp + pushes > MASQ_BLAS_STACK) {
      fault = MASQ_FAULT_STACK_FULL | (MASQ_LEVEL_BV << 8);
      fault_node = node;
      break;
    }
    if (far_t != inf_()) {
      stack_node[sp] = far_i;
      stack_t[sp] = far_t;
      sp = sp + 1;
    }
    if (near_t != inf_()) {
      stack_node[sp] = near_i;
      stack_t[sp] = near_t;
      sp = sp + 1;
    }
  }
  res.hit = fault != 0 ? hit_fault(KD_ARG ray.tmax, fault, fault_node, sp) : hit_from_nearest(KD_ARG best);
  return res;
}

KERNEL_NS_END
#endif
