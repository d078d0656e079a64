// Two-level closest-hit traversal, as RT hardware does it with instances: walk the
// TLAS, transform the ray into each instance's object space, test the BLAS (for a
// masquerade instance: the unit box, then the world-space intersector), keep the
// nearest hit. Children are visited front to back; subtrees beyond the current
// nearest hit are skipped when popped. The BLAS walk: kernels/traverse_blas.h.
#ifndef MASQ_KERNEL_TRAVERSE_H
#define MASQ_KERNEL_TRAVERSE_H
#include "traverse_blas.h"
#include "masq_instance.h"
#include "masq_entry_simd_cpp.h"
#if defined(MASQ_LANG_CPP)
#include <cstring>
#endif

KERNEL_NS_BEGIN

// A TLAS node's visit order for this kernel's query (child_order.h; MASQ_TLAS_STARTS_LAST:
// a TLAS of masquerade entries). BLAS nodes: order_children.
FN ChildOrder order_tlas_children(WideHits wh, int width, float tmin) {
  if (MASQ_ANY_HIT && MASQ_TLAS_STARTS_LAST) return order_children_occlusion(wh, width, tmin);
  return order_children(wh, width);
}

STRUCT_BEGIN(TraceOut)
  Hit hit;
  RayStats stats;
STRUCT_END(TraceOut)

FN Hit hit_from_nearest(KD_PARAM Nearest n) {
  Hit h;
  h.t = n.prim >= 0 ? n.t : inf_();
  h.prim = n.prim;
  h.geom = n.geom;
  h.inst = n.inst;
  vec3 wn = VEC3(0.0f, 0.0f, 0.0f);
  if (n.prim >= 0) {
    wn = affine_normal_to_world(affine_from_frame(KD(frames)[n.inst]), n.normal);
    float l = length(wn);
    wn = l > 0.0f ? wn / l : wn;
  }
  h.normal[0] = wn.x;
  h.normal[1] = wn.y;
  h.normal[2] = wn.z;
  h.u = n.u;
  h.v = n.v;
  h.fault = 0;
  h.fault_node = 0;
  h.fault_depth = 0;
  return h;
}

// Validity is read from the float bits with integer masks, not isnan/isinf: a driver
// that compiles with fast-math assumptions (no NaN, no Inf) may fold those to false,
// and an invalid ray would then be traversed (docs/robustness.md, "Float semantics").
// Finite: the exponent is not all ones; NaN: all-ones exponent, nonzero mantissa.
FN bool bits_finite(float x) { return (f2u_(x) & 0x7f800000u) != 0x7f800000u; }
FN bool bits_nan(float x) { return (f2u_(x) & 0x7fffffffu) > 0x7f800000u; }

FN bool ray_is_valid(vec3 o, vec3 d, float tmin, float tmax) {
  return bits_finite(o.x) && bits_finite(o.y) && bits_finite(o.z) && bits_finite(d.x) && bits_finite(d.y) &&
         bits_finite(d.z) && dot(d, d) > 0.0f && !bits_nan(tmin) && !bits_nan(tmax) && tmin <= tmax;
}

// A ray the walk stopped (fault != 0): a miss carrying the fault (Hit, layout.h).
FN Hit hit_fault(KD_PARAM float tmax, int fault, int node, int depth) {
  Hit h = hit_from_nearest(KD_ARG nearest_none(tmax));
  h.fault = fault;
  h.fault_node = node;
  h.fault_depth = depth;
  return h;
}

// A masquerade entry whose unit box the ray enters (ref < 0: compact entry -1 - ref, else
// a full instance): its primitive's intersector on the world ray taken into the scene
// instance's frame, within the nearest hit so far.
FN Nearest masquerade_hit(KD_PARAM int ref, int geom, int prim, int scene_inst, vec3 wo, vec3 wd, float tmin,
                          Nearest best) {
  Affine f = affine_from_frame(KD(frames)[scene_inst]);
  Geometry g = KD(geoms)[geom];
  vec3 po = affine_point(f, wo);
  vec3 pd = affine_vector(f, wd);
#if defined(MASQ_LANG_CPP)
  // cpu: a compact entry's curve from the copy in entry order (host/cpu/entry_curves.h),
  // whose line the leaf's prefetch already asked for.
  bool copied = MASQ_HAVE_CURVES && ref < 0 && g.type == MASQ_CPU_ENTRY_COPY_TYPE && KD(entry_curves) != nullptr;
  PrimHit ph = copied ? intersect_curve_record(KD(entry_curves)[-1 - ref], po, pd, tmin, best.t)
                      : intersect_primitive(KD_ARG g, prim, po, pd, tmin, best.t);
#else
  PrimHit ph = intersect_primitive(KD_ARG g, prim, po, pd, tmin, best.t);
#endif
  return nearest_take(best, ph, prim, geom, scene_inst);
}

#if defined(MASQ_LANG_CPP)
// A TLAS leaf's compact entries nearest box first (the cpu's order where it cannot change
// the hit: entry_leaf_nearest_first): the entries j < n of leaf_refs whose unit boxes eb
// the ray enters, by entry distance, each against the nearest hit so far. Returns
// whether a hit taken tied the one it replaced at exactly its distance (which of two tied
// hits is kept depends on the order).
FN_INLINED bool entries_nearest_first(KD_PARAM const int* leaf_refs, int n, const simd::EntryBoxes4& eb, vec3 wo,
                                      vec3 wd, float tmin, Nearest& best) {
  int order[4];
  const int m = simd::entries_by_distance(eb, n, tmin, best.t, order);
  bool tie = false;
  for (int k = 0; k < m; ++k) {
    const int j = order[k];
    if (!simd::entry_in_box(eb, j, tmin, best.t)) continue;
    const int ref = leaf_refs[j];
    const MasqInstance c = KD(masq_instances)[-1 - ref];
    const MasqOwner owner = KD(masq_owners)[masq_owner_index(c)];
    const Nearest was = best;
    best = masquerade_hit(KD_ARG ref, owner.geom, c.prim, owner.scene_inst, wo, wd, tmin, best);
    if (was.prim >= 0 && best.t == was.t && std::memcmp(&best, &was, sizeof best) != 0) tie = true;
  }
  return tie;
}

// A leaf of n <= 4 compact entries (their unit boxes eb) taken nearest box first, so that
// a near hit shuts out the farther entries' calls: under sah4 a leaf holds four entries,
// where it held one or two below nodes visited front to back. The nearest hit is then
// the reference order's unless two hits tie at exactly its distance: then the leaf is
// taken again in reference order from where it started.
FN_INLINED void entry_leaf_nearest_first(KD_PARAM const int* leaf_refs, int n, const simd::EntryBoxes4& eb, vec3 wo,
                                         vec3 wd, float tmin, Nearest& best) {
  const Nearest start = best;
  if (!entries_nearest_first(KD_ARG leaf_refs, n, eb, wo, wd, tmin, best)) return;
  best = start;
  for (int j = 0; j < n; ++j) {
    if (!simd::entry_in_box(eb, j, tmin, best.t)) continue;
    const int ref = leaf_refs[j];
    const MasqInstance c = KD(masq_instances)[-1 - ref];
    const MasqOwner owner = KD(masq_owners)[masq_owner_index(c)];
    best = masquerade_hit(KD_ARG ref, owner.geom, c.prim, owner.scene_inst, wo, wd, tmin, best);
  }
}
#endif

// budget: TraceParams::step_budget, for the TLAS walk and each BLAS walk alike.
// Inlined into the cpu unit's loop over its rays: returned from a call, the hit was
// stored in small pieces and read back as 32-byte words (a failed store forward per ray).
FN_INLINED TraceOut trace_closest(KD_PARAM Ray ray, int tlas_root, int budget) {
  TraceOut res;
  res.stats.tlas_nodes = 0;
  res.stats.blas_nodes = 0;
  res.stats.transforms = 0;
  res.stats.isect_calls = 0;
  vec3 wo = V3(ray.org);
  vec3 wd = V3(ray.dir);
  float tmin = ray.tmin;
  Nearest best = nearest_none(ray.tmax);
  // Invalid rays (NaN/Inf components, zero direction, empty interval) miss by contract.
  if (tlas_root < 0 || !ray_is_valid(wo, wd, tmin, ray.tmax)) {
    res.hit = hit_from_nearest(KD_ARG nearest_none(ray.tmax));
    return res;
  }
  if (MASQ_SINGLE_BLAS) {
    Instance only = KD(instances)[0];
    BlasOut bo = traverse_blas(KD_ARG only.blas_root, only.geom, only.scene_inst, wo, wd, 0, VEC3(0.0f, 0.0f, 0.0f), wo,
                               wd, tmin, ray.tmax, best, budget);
    if (MASQ_STATS) {
      res.stats.blas_nodes = bo.nodes;
      res.stats.isect_calls = bo.isect_calls;
    }
    res.hit = bo.fault != 0 ? hit_fault(KD_ARG ray.tmax, bo.fault, bo.fault_node, bo.fault_depth)
                            : hit_from_nearest(KD_ARG bo.nearest);
    return res;
  }
  vec3 inv_d = safe_rcp3(wd);
  int stack_node[MASQ_STACK_DIM(MASQ_TLAS_STACK)];
  float stack_t[MASQ_STACK_DIM(MASQ_TLAS_STACK)];
  int sp = 0;
  int node = tlas_root; // held, as in traverse_blas
  float node_t = tmin;
  bool held = true;
  int steps = 0;
  bool done = false; // an occlusion query's hit, or a fault (no return inside the loops: traverse_blas)
  int fault = 0;
  int fault_node = 0;
  int fault_depth = 0;
  while (!done && (held || sp > 0)) {
    if (!held) {
      sp = sp - 1;
      node = stack_node[sp];
      node_t = stack_t[sp];
    }
    held = false;
    if (MASQ_STEP_CHECK) {
      if (steps >= budget) {
        fault = MASQ_FAULT_STEP_BUDGET | (MASQ_LEVEL_TLAS << 8);
        fault_node = node;
        fault_depth = sp;
        break;
      }
      steps = steps + 1;
    }
    if (node_t > best.t) continue;
    if (MASQ_STATS) res.stats.tlas_nodes = res.stats.tlas_nodes + 1;
    // The builders rotate BLAS nodes only (o4), so TLAS nodes carry no exit bounds; the
    // nearest hit so far bounds t all the same (+inf before one: a rotated node would
    // then be entered by every ray, never missed).
    WideHits wh = node_hits(KD_ARG node, wo, wd, inv_d, 0, VEC3(0.0f, 0.0f, 0.0f), tmin, best.t, best.t);
    // The hit leaves nearest first, then the hit inner children pushed farthest first
    // (occlusion queries over masquerade entries: order_tlas_children's order).
#if defined(MASQ_LANG_CPP)
    // cpu: each set ordered on its own, as traverse_blas does (the same two orders: a
    // stable sort keeps a subset's order, and so do the occlusion order's two bit scans),
    // so neither loop steps over the other's slots.
    simd::SlotMasks hit = simd::slot_masks(wh.tnear, wh.count, node_width());
    ChildOrder leaves;
    ChildOrder inner;
    if (MASQ_ANY_HIT && MASQ_TLAS_STARTS_LAST) {
      unsigned starts = simd::start_slots(wh.tnear, tmin, node_width());
      leaves.n = simd::occlusion_slots(hit.leaves, starts, leaves.slot);
      inner.n = simd::occlusion_slots(hit.inner, starts, inner.slot);
    } else {
      leaves.n = simd::sorted_slots(wh.tnear, hit.leaves, leaves.slot);
      inner.n = simd::sorted_slots(wh.tnear, hit.inner, inner.slot);
    }
    for (int k = 0; k < inner.n; ++k) prefetch_node(KD_ARG wh.child[inner.slot[k]]);
#else
    ChildOrder leaves = order_tlas_children(wh, node_width(), tmin);
    ChildOrder inner = leaves;
#endif
    for (int k = 0; k < leaves.n; ++k) {
      int i = leaves.slot[k];
      if (wh.count[i] <= 0 || wh.tnear[i] > best.t) continue;
#if defined(MASQ_LANG_CPP)
      // cpu: every entry of the leaf asked for at once, so their misses overlap; a compact
      // entry's curve too (its copy in entry order needs no load of the entry first).
      // A leaf of at most four compact entries alone has their unit boxes tested at once
      // (masq_entry_simd_cpp.h, the scalar test's bits); each is then taken in order
      // against the nearest hit so far, as the loop below takes them.
      bool lanes = wh.count[i] <= 4;
      for (int j = 0; j < wh.count[i]; ++j) {
        int ref = KD(refs)[wh.child[i] + j];
        if (ref < 0) {
          __builtin_prefetch(KD(masq_instances) + (-1 - ref));
          if (KD(entry_curves) != nullptr) __builtin_prefetch(KD(entry_curves) + (-1 - ref));
        } else {
          __builtin_prefetch(KD(instances) + ref);
          lanes = false;
        }
      }
      if (lanes) {
        const int* leaf_refs = KD(refs) + wh.child[i];
        simd::EntryBoxes4 eb =
            simd::entry_boxes4(KD(masq_instances), leaf_refs, wh.count[i], wo, wd, wh.tfar[i], MASQ_ROBUST != 0);
        // Closest hits in robust mode without counters, on a TLAS of compact entries whose
        // primitives' intersectors find a hit whatever the window's far end
        // (KernelData::entry_packets): nearest box first.
        if (MASQ_ROBUST && !MASQ_ANY_HIT && !MASQ_STATS && KD(entry_packets) != 0) {
          entry_leaf_nearest_first(KD_ARG leaf_refs, wh.count[i], eb, wo, wd, tmin, best);
          continue;
        }
        for (int j = 0; j < wh.count[i]; ++j) {
          int ref = leaf_refs[j];
          if (MASQ_STATS) {
            res.stats.transforms = res.stats.transforms + 1;
            res.stats.blas_nodes = res.stats.blas_nodes + 1;
          }
          if (!simd::entry_in_box(eb, j, tmin, best.t)) continue;
          MasqInstance c = KD(masq_instances)[-1 - ref];
          MasqOwner owner = KD(masq_owners)[masq_owner_index(c)];
          if (MASQ_STATS) res.stats.isect_calls = res.stats.isect_calls + 1;
          best = masquerade_hit(KD_ARG ref, owner.geom, c.prim, owner.scene_inst, wo, wd, tmin, best);
          if (MASQ_ANY_HIT && best.prim >= 0) {
            done = true;
            break;
          }
        }
        if (done) break;
        continue;
      }
#endif
      for (int j = 0; j < wh.count[i]; ++j) {
        // ref >= 0: an Instance; ref < 0: compact masquerade entry ~ref (same branch).
        int ref = KD(refs)[wh.child[i] + j];
        Affine m;
        int blas_root = -1;
        int geom = 0;
        int prim = 0;
        int scene_inst = 0;
        if (ref >= 0) {
          Instance inst = KD(instances)[ref];
          m = affine_from_instance(inst);
          blas_root = inst.blas_root;
          geom = inst.geom;
          prim = inst.prim;
          scene_inst = inst.scene_inst;
        } else {
          MasqInstance c = KD(masq_instances)[-1 - ref];
          MasqOwner owner = KD(masq_owners)[masq_owner_index(c)];
          m = affine_from_masq(c);
          geom = owner.geom;
          prim = c.prim;
          scene_inst = owner.scene_inst;
        }
        vec3 oo = affine_point(m, wo);
        vec3 od = affine_vector(m, wd);
        if (MASQ_STATS) res.stats.transforms = res.stats.transforms + 1;
        if (blas_root >= 0) {
          // Cluster: boxes in the cluster's frame, primitives on the scene-frame ray.
          bool cluster = prim == MASQ_INST_CLUSTER;
          vec3 po = oo;
          vec3 pd = od;
          vec3 pad = VEC3(0.0f, 0.0f, 0.0f);
          if (cluster) {
            Affine f = affine_from_frame(KD(frames)[scene_inst]);
            po = affine_point(f, wo);
            pd = affine_vector(f, wd);
            if (MASQ_ROBUST) pad = transform_pad(m, wo, wd, wh.tfar[i]);
          }
          int padded = (cluster && MASQ_ROBUST) ? 1 : 0;
          BlasOut bo = traverse_blas(KD_ARG blas_root, geom, scene_inst, oo, od, padded, pad, po, pd,
                                     tmin, wh.tfar[i], best, budget);
          best = bo.nearest;
          if (MASQ_STATS) {
            res.stats.blas_nodes = res.stats.blas_nodes + bo.nodes;
            res.stats.isect_calls = res.stats.isect_calls + bo.isect_calls;
          }
          if (bo.fault != 0) {
            fault = bo.fault;
            fault_node = bo.fault_node;
            fault_depth = bo.fault_depth;
            done = true;
            break;
          }
          if (MASQ_ANY_HIT && best.prim >= 0) {
            done = true;
            break;
          }
        } else {
          // Masquerade: the unit-box test is the OBB cull; the intersector then runs
          // on the untransformed ray (in the scene instance's frame).
          if (MASQ_STATS) res.stats.blas_nodes = res.stats.blas_nodes + 1;
          bool in_box = MASQ_ROBUST ? hit_unit_box_padded(m, wo, wd, oo, od, tmin, best.t, wh.tfar[i])
                                    : hit_unit_box(oo, od, tmin, best.t);
          if (!in_box) continue;
          if (MASQ_STATS) res.stats.isect_calls = res.stats.isect_calls + 1;
          best = masquerade_hit(KD_ARG ref, geom, prim, scene_inst, wo, wd, tmin, best);
          if (MASQ_ANY_HIT && best.prim >= 0) {
            done = true;
            break;
          }
        }
      }
      if (done) break;
    }
    if (done) break;
    for (int k = inner.n - 1; k >= 0; --k) {
      int i = inner.slot[k];
      if (wh.count[i] != 0) continue;
      if (held) {
        if (sp >= MASQ_TLAS_STACK) {
          fault = MASQ_FAULT_STACK_FULL | (MASQ_LEVEL_TLAS << 8);
          fault_node = node;
          fault_depth = sp;
          done = true;
          break;
        }
        stack_node[sp] = node;
        stack_t[sp] = node_t;
        sp = sp + 1;
      }
      node = wh.child[i];
      node_t = wh.tnear[i];
      held = true;
    }
  }
  res.hit = fault != 0 ? hit_fault(KD_ARG ray.tmax, fault, fault_node, fault_depth) : hit_from_nearest(KD_ARG best);
  return res;
}

KERNEL_NS_END
#endif
