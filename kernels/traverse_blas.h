// One BLAS walked for one ray (the two-level walk of kernels/traverse.h calls it per
// instance; a scene of one BLAS instance is this walk alone): wide nodes front to back,
// each node's hit leaves intersected nearest first, its hit inner children pushed
// farthest first (occlusion queries: order_blas_inner), the nearest hit so far pruning
// what lies beyond it. On cpu the leaves' capsules go four or eight at a time.
#ifndef MASQ_KERNEL_TRAVERSE_BLAS_H
#define MASQ_KERNEL_TRAVERSE_BLAS_H
#include "node_formats.h"
#include "child_order.h"
#include "intersect_primitive.h"
#include "capsule_simd_cpp.h"
#include "triangle_simd_cpp.h"

KERNEL_NS_BEGIN

// A BLAS node's visit order for its hit inner children, given the node's order `co`
// (MASQ_BLAS_STARTS_LAST: occlusion queries take the children the ray starts in last,
// child_order.h). Its hit leaves always go nearest first.
FN ChildOrder order_blas_inner(WideHits wh, ChildOrder co, int width, float tmin) {
  if (MASQ_ANY_HIT && MASQ_BLAS_STARTS_LAST) return order_children_occlusion(wh, width, tmin);
  return co;
}

STRUCT_BEGIN(Nearest)
  float t;
  int prim;
  int geom;
  int inst;
  vec3 normal; // object space of scene instance `inst`
  float u;
  float v;
STRUCT_END(Nearest)

// fault, fault_node, fault_depth: as in Hit (layout.h); 0 when the walk finished.
STRUCT_BEGIN(BlasOut)
  Nearest nearest;
  int nodes;
  int isect_calls;
  int fault;
  int fault_node;
  int fault_depth;
STRUCT_END(BlasOut)

FN Nearest nearest_none(float tmax) {
  Nearest n;
  n.t = tmax;
  n.prim = -1;
  n.geom = -1;
  n.inst = -1;
  n.normal = VEC3(0.0f, 0.0f, 0.0f);
  n.u = 0.0f;
  n.v = 0.0f;
  return n;
}

// The intersector's hit, if any, becomes the nearest (it was searched up to nearest.t).
FN Nearest nearest_take(Nearest n, PrimHit ph, int prim, int geom, int inst) {
  if (ph.hit == 0) return n;
  n.t = ph.t;
  n.prim = prim;
  n.geom = geom;
  n.inst = inst;
  n.normal = ph.normal;
  n.u = ph.u;
  n.v = ph.v;
  return n;
}

STRUCT_BEGIN(LeafOut)
  Nearest nearest;
  int isect_calls;
#if defined(MASQ_LANG_CPP)
  // cpu: hits taken at exactly the nearest hit's distance (a tie, decided by the order
  // the primitives are met in), for the packet walk (packet_walk_cpp.h), which meets
  // them in another order and leaves such rays to this walk. The walk here ignores it.
  int ties;
#endif
STRUCT_END(LeafOut)

#if defined(MASQ_LANG_CPP)
// cpu: whether a hit at t, about to be taken, ties the nearest hit so far (a hit, not
// the ray's end).
FN_INLINED int tie_of(const Nearest& n, float t) { return t == n.t && n.prim >= 0 ? 1 : 0; }

// cpu: lanes [lane0, lane0 + count) of a capsule test, one leaf's references from refs[first]
// in order, each taken within the nearest hit so far. Returns true when an occlusion
// query has its hit.
template <int L>
FN_INLINED bool take_leaf_lanes(KD_PARAM const simd::CapsuleHitsN<L>& c, int lane0, int first, int count, int geom_id,
                                int inst_id, LeafOut& lo) {
  for (int j = 0; j < count; ++j) {
    if (MASQ_STATS) lo.isect_calls = lo.isect_calls + 1;
    int l = lane0 + j;
    if (c.hit[l] == 0 || !(c.t[l] <= lo.nearest.t)) continue;
    lo.ties += tie_of(lo.nearest, c.t[l]);
    PrimHit ph;
    ph.hit = 1;
    ph.t = c.t[l];
    ph.normal = VEC3(c.nx[l], c.ny[l], c.nz[l]);
    ph.u = c.u[l];
    ph.v = 0.0f;
    lo.nearest = nearest_take(lo.nearest, ph, KD(refs)[first + j], geom_id, inst_id);
    if (MASQ_ANY_HIT) return true;
  }
  return false;
}

// cpu: lanes [0, count) of a triangle test, one leaf's references from refs[first] in
// order, each taken within the nearest hit so far by intersect_triangle's own scaled
// comparison (tt <= tmax * det, tmin <= tmax), so the loop's result bit for bit. Returns
// true when an occlusion query has its hit.
FN_INLINED bool take_triangle_lanes(KD_PARAM const simd::TriangleHits4& c, int first, int count, float tmin,
                                    int geom_id, int inst_id, LeafOut& lo) {
  for (int j = 0; j < count; ++j) {
    if (MASQ_STATS) lo.isect_calls = lo.isect_calls + 1;
    if (c.hit[j] == 0 || !(c.tt[j] <= lo.nearest.t * c.det[j]) || !(tmin <= lo.nearest.t)) continue;
    lo.ties += tie_of(lo.nearest, c.t[j]);
    PrimHit ph;
    ph.hit = 1;
    ph.t = c.t[j];
    ph.normal = VEC3(c.nx[j], c.ny[j], c.nz[j]);
    ph.u = c.u[j];
    ph.v = c.v[j];
    lo.nearest = nearest_take(lo.nearest, ph, KD(refs)[first + j], geom_id, inst_id);
    if (MASQ_ANY_HIT) return true;
  }
  return false;
}
#endif

// The leaf's `count` references from refs[first] in order, each intersected within the
// nearest hit so far; an occlusion query stops at the first hit. Inlined on the cpu
// (as are intersect_primitive and intersect_triangle): called, the nearest hit came
// back through memory in 4-byte pieces and was read as 16-byte words, and the vec3
// arguments went the same way, a failed store forward each (perf: a fifth of a trace
// of the default scene's ground plane, on the instruction after each such load).
FN_INLINED LeafOut intersect_leaf(KD_PARAM Geometry g, int first, int count, int geom_id, int inst_id, vec3 po,
                                  vec3 pd, float tmin, Nearest nearest) {
  LeafOut lo;
  lo.nearest = nearest;
  lo.isect_calls = 0;
#if defined(MASQ_LANG_CPP)
  lo.ties = 0;
  // cpu: robust capsules four at a time (capsule_simd_cpp.h). A lane computed within
  // the leaf's starting interval gives the scalar call's answer whenever its crossing
  // lies within the nearest hit so far, and a miss of the scalar call otherwise, so
  // taking the lanes in order as below is the loop's result, bit for bit. The capsules
  // come from the cpu's leaf-ordered row copy (KernelData::leaf_capsule_rows), the same
  // values the references name; a reference is read only for a hit.
  if (MASQ_ROBUST && MASQ_HAVE_CAPSULES && g.type == MASQ_CPU_LEAF_COPY_TYPE) {
    for (int j0 = 0; j0 < count; j0 += 4) {
      int n = min(count - j0, 4);
      simd::CapsuleLanes<simd::F4> caps = simd::capsule_rows4(KD(leaf_capsule_rows), KD(leaf_capsule_stride), first + j0);
      simd::CapsuleHits4 c =
          simd::capsule_hits<simd::F4, simd::I4>(caps, simd::lanes_below(n), po, pd, tmin, lo.nearest.t);
      if (take_leaf_lanes<4>(KD_ARG c, 0, first + j0, n, geom_id, inst_id, lo)) return lo;
    }
    return lo;
  }
  // cpu: robust triangles four at a time (triangle_simd_cpp.h), each lane the scalar
  // call's bits; the lanes are taken in order as the loop below takes the calls. Leaves
  // of one or two triangles stay with the loop: they would fill half the lanes or less
  // and still pay the whole gather (a choice, not measured: the default scene's ground,
  // whose leaves hold one triangle, runs the loop either way).
  if (MASQ_ROBUST && MASQ_HAVE_TRIANGLES && g.type == MASQ_PRIM_TRIANGLE && count > 2) {
    for (int j0 = 0; j0 < count; j0 += 4) {
      int n = min(count - j0, 4);
      simd::TriangleLanes4 tris = simd::triangle_lanes4(KD(triangles), g.first, KD(refs) + first + j0, n);
      simd::TriangleHits4 c = simd::triangle_hits4(tris, simd::lanes_below(n), po, pd, tmin, lo.nearest.t);
      if (take_triangle_lanes(KD_ARG c, first + j0, n, tmin, geom_id, inst_id, lo)) return lo;
    }
    return lo;
  }
#endif
  for (int j = 0; j < count; ++j) {
    int prim = KD(refs)[first + j];
    if (MASQ_STATS) lo.isect_calls = lo.isect_calls + 1;
    PrimHit ph = intersect_primitive(KD_ARG g, prim, po, pd, tmin, lo.nearest.t);
#if defined(MASQ_LANG_CPP)
    lo.ties += ph.hit != 0 ? tie_of(lo.nearest, ph.t) : 0;
#endif
    lo.nearest = nearest_take(lo.nearest, ph, prim, geom_id, inst_id);
    if (MASQ_ANY_HIT && lo.nearest.prim >= 0) break;
  }
  return lo;
}

#if defined(MASQ_LANG_CPP)
// cpu: the hit leaves of one capsule node visit (slot[0..n-1], nearest entry first).
// Two leaves of at most four capsules share one eight-lane capsule test (AVX), the
// first in lanes 0-3, the second in lanes 4-7; the cpu's sah4 leaves hold four capsules,
// and secondary rays often enter two or more leaves of a node. A pair is tested within
// the nearest hit when it is formed; taking the lanes leaf by leaf, each within the
// nearest hit so far, gives the one-source loop's result bit for bit (intersect_leaf's
// argument), and a leaf entered beyond the nearest hit is skipped, as that loop skips it,
// when its turn comes. A leaf without a partner, or of more than four, goes through
// intersect_leaf.
FN_INLINED LeafOut capsule_leaves(KD_PARAM const WideHits& wh, const int* slot, int n, int geom_id, int inst_id,
                                  vec3 po, vec3 pd, float tmin, Nearest nearest) {
  LeafOut lo;
  lo.nearest = nearest;
  lo.isect_calls = 0;
#if defined(MASQ_LANG_CPP)
  lo.ties = 0;
#endif
  Geometry g = KD(geoms)[geom_id];
  int k = 0;
  while (k < n) {
    int a = slot[k];
    k = k + 1;
    if (wh.tnear[a] > lo.nearest.t) continue;
    int b = -1;
    if (wh.count[a] <= 4) {
      while (k < n && b < 0) {
        int i = slot[k];
        if (wh.tnear[i] > lo.nearest.t) k = k + 1; // beyond the nearest hit: skipped now and at its turn
        else if (wh.count[i] <= 4) b = i;
        else break;
      }
    }
    if (b < 0) {
      LeafOut one = intersect_leaf(KD_ARG g, wh.child[a], wh.count[a], geom_id, inst_id, po, pd, tmin, lo.nearest);
      lo.nearest = one.nearest;
      if (MASQ_STATS) lo.isect_calls = lo.isect_calls + one.isect_calls;
      lo.ties += one.ties;
      if (MASQ_ANY_HIT && lo.nearest.prim >= 0) return lo;
      continue;
    }
    k = k + 1;
    simd::I8 valid = simd::I8{0, 1, 2, 3, 0, 1, 2, 3} <
                     simd::I8{wh.count[a], wh.count[a], wh.count[a], wh.count[a], wh.count[b], wh.count[b], wh.count[b],
                              wh.count[b]};
    simd::CapsuleHitsN<8> c = simd::capsule_hits<simd::F8, simd::I8>(
        simd::capsule_rows8(KD(leaf_capsule_rows), KD(leaf_capsule_stride), wh.child[a], wh.child[b]), valid, po, pd,
        tmin, lo.nearest.t);
    if (take_leaf_lanes<8>(KD_ARG c, 0, wh.child[a], wh.count[a], geom_id, inst_id, lo)) return lo;
    if (wh.tnear[b] > lo.nearest.t) continue;
    if (take_leaf_lanes<8>(KD_ARG c, 4, wh.child[b], wh.count[b], geom_id, inst_id, lo)) return lo;
  }
  return lo;
}
#endif

// (o, d): the ray the boxes are tested with; (po, pd): the ray the primitives are
// intersected with. They are the same ray for an ordinary BLAS instance; for a cluster
// instance (o, d) is in the cluster's frame and (po, pd) in the scene instance's, and
// padded != 0 grows every box by pad (the error bound of the fp32 transform to (o, d)).
// root_tbound: no primitive of the tree is hit beyond it (the exit distance of the
// tree's box in the TLAS); the o4 format's rotated nodes pad by it (node_hits), and
// each node passes its children's exit distances on, held with them on the stack.
// budget: the most loop steps the walk may take (TraceParams::step_budget); a walk past
// it, or a push onto a full stack, stops with res.fault set (MASQ_STEP_CHECK).
// The loops hold no return: an early exit sets `done` and breaks, since a compiler merges
// returns from inside loops through a value left undefined on the other paths.
FN_INLINED BlasOut traverse_blas(KD_PARAM int root, int geom_id, int inst_id, vec3 o, vec3 d, int padded,
                                 vec3 pad, vec3 po, vec3 pd, float tmin, float root_tbound, Nearest nearest,
                                 int budget) {
  const bool tbounds = MASQ_NODE_FORMAT == MASQ_NODES_O4;
  BlasOut res;
  res.nearest = nearest;
  res.nodes = 0;
  res.isect_calls = 0;
  res.fault = 0;
  res.fault_node = 0;
  res.fault_depth = 0;
  Geometry g = KD(geoms)[geom_id];
  vec3 inv_d = safe_rcp3(d);
  int stack_node[MASQ_STACK_DIM(MASQ_BLAS_STACK)];
  float stack_t[MASQ_STACK_DIM(MASQ_BLAS_STACK)];
  float stack_tf[MASQ_STACK_DIM(MASQ_BLAS_STACK)];
  int sp = 0;
  // The node visited next is held here, not pushed and popped: the nearest inner child
  // of the node just visited (the one the stack would pop next), else the stack's top.
  int node = root;
  float node_t = tmin;
  float node_tf = root_tbound;
  bool held = true;
  int steps = 0;
  bool done = false; // an occlusion query's hit, or a fault
#if defined(MASQ_LANG_CPP)
  O4RayCache o4_cache; // (o4: the ray in the last rotated node's frame, node_formats.h)
#endif
  while (!done && (held || sp > 0)) {
    if (!held) {
      sp = sp - 1;
      node = stack_node[sp];
      node_t = stack_t[sp];
      if (tbounds) node_tf = stack_tf[sp];
    }
    held = false;
    if (MASQ_STEP_CHECK) {
      if (steps >= budget) {
        res.fault = MASQ_FAULT_STEP_BUDGET | (MASQ_LEVEL_BLAS << 8);
        res.fault_node = node;
        res.fault_depth = sp;
        break;
      }
      steps = steps + 1;
    }
    if (node_t > res.nearest.t) continue;
    if (MASQ_STATS) res.nodes = res.nodes + 1;
#if defined(MASQ_LANG_CPP)
    WideHits wh = node_hits_cached(KD_ARG node, o, d, inv_d, padded, pad, tmin, res.nearest.t, node_tf, o4_cache);
#else
    WideHits wh = node_hits(KD_ARG node, o, d, inv_d, padded, pad, tmin, res.nearest.t, node_tf);
#endif
#if defined(MASQ_LANG_CPP)
    {
      // cpu: the visits of the loops below, in their order, without their scan of every
      // slot: the leaves loop takes the hit leaves in entry order and the push loop the
      // hit inner children, so each is sorted on its own (simd::sorted_slots; the inner
      // children of MASQ_BLAS_STARTS_LAST's occlusion queries by two bit scans instead).
      // The inner children are ordered first, so their nodes are asked for before the
      // leaves are tested (prefetch_node).
      simd::SlotMasks hit = simd::slot_masks(wh.tnear, wh.count, node_width());
      int inner[MASQ_WIDTH8];
      int n_inner = MASQ_ANY_HIT && MASQ_BLAS_STARTS_LAST
                        ? simd::occlusion_slots(hit.inner, simd::start_slots(wh.tnear, tmin, node_width()), inner)
                        : simd::sorted_slots(wh.tnear, hit.inner, inner);
      for (int k = 0; k < n_inner; ++k) prefetch_node(KD_ARG wh.child[inner[k]]);
      int slot[MASQ_WIDTH8];
      int n = simd::sorted_slots(wh.tnear, hit.leaves, slot);
      if (MASQ_ROBUST && MASQ_HAVE_CAPSULES && g.type == MASQ_CPU_LEAF_COPY_TYPE && n > 0) {
        LeafOut lo = capsule_leaves(KD_ARG wh, slot, n, geom_id, inst_id, po, pd, tmin, res.nearest);
        res.nearest = lo.nearest;
        if (MASQ_STATS) res.isect_calls = res.isect_calls + lo.isect_calls;
        if (MASQ_ANY_HIT && res.nearest.prim >= 0) return res;
        n = 0;
      }
      for (int k = 0; k < n; ++k) {
        int i = slot[k];
        if (wh.tnear[i] > res.nearest.t) continue;
        LeafOut lo = intersect_leaf(KD_ARG g, wh.child[i], wh.count[i], geom_id, inst_id, po, pd, tmin, res.nearest);
        res.nearest = lo.nearest;
        if (MASQ_STATS) res.isect_calls = res.isect_calls + lo.isect_calls;
        if (MASQ_ANY_HIT && res.nearest.prim >= 0) return res;
      }
      for (int k = n_inner - 1; k >= 0; --k) {
        if (held) {
          if (sp >= MASQ_BLAS_STACK) {
            res.fault = MASQ_FAULT_STACK_FULL | (MASQ_LEVEL_BLAS << 8);
            res.fault_node = node;
            res.fault_depth = sp;
            return res;
          }
          stack_node[sp] = node;
          stack_t[sp] = node_t;
          if (tbounds) stack_tf[sp] = node_tf;
          sp = sp + 1;
        }
        node = wh.child[inner[k]];
        node_t = wh.tnear[inner[k]];
        node_tf = wh.tfar[inner[k]];
        held = true;
      }
      continue;
    }
#endif
    ChildOrder co = order_children(wh, node_width());
    // Leaves now (nearest first), inner nodes pushed farthest first so nearest pops next.
    for (int k = 0; k < co.n; ++k) {
      int i = co.slot[k];
      if (wh.count[i] <= 0 || wh.tnear[i] > res.nearest.t) continue;
      LeafOut lo = intersect_leaf(KD_ARG g, wh.child[i], wh.count[i], geom_id, inst_id, po, pd, tmin, res.nearest);
      res.nearest = lo.nearest;
      if (MASQ_STATS) res.isect_calls = res.isect_calls + lo.isect_calls;
      if (MASQ_ANY_HIT && res.nearest.prim >= 0) {
        done = true; // occlusion: any hit will do
        break;
      }
    }
    if (done) break;
    // The inner children pushed last-visited first (order_blas_inner's order).
    ChildOrder ci = order_blas_inner(wh, co, node_width(), tmin);
    for (int k = ci.n - 1; k >= 0; --k) {
      int i = ci.slot[k];
      if (wh.count[i] != 0) continue;
      if (held) {
        if (sp >= MASQ_BLAS_STACK) {
          res.fault = MASQ_FAULT_STACK_FULL | (MASQ_LEVEL_BLAS << 8);
          res.fault_node = node;
          res.fault_depth = sp;
          done = true;
          break;
        }
        stack_node[sp] = node;
        stack_t[sp] = node_t;
        if (tbounds) stack_tf[sp] = node_tf;
        sp = sp + 1;
      }
      node = wh.child[i];
      node_t = wh.tnear[i];
      node_tf = wh.tfar[i];
      held = true;
    }
  }
  return res;
}

KERNEL_NS_END
#endif
