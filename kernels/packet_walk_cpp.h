// cpu only: eight camera rays walked through one tree together (a packet), each with the
// node test, leaf tests and nearest-hit rule of the single-ray walk, in a shared node
// order. The tree is one BLAS of capsules (traverse_blas's walk) or a TLAS of compact
// masquerade entries (trace_closest's TLAS walk). A pinhole camera's neighbouring rays
// mostly enter the same nodes: the packet fetches, orders, pushes and pops each node once
// for all of them instead of once per ray.
//
// Why every ray gets the single-ray walk's answer, bit for bit (docs/kernels.md, "Packets"):
// - The packet takes a node's children in the order of their nearest entry over the
//   packet, not each ray's own, so a ray may meet its primitives in another order. In
//   robust mode a box holds every crossing of what lies in it (the boxes are padded,
//   the slab test widened; a masquerade entry's unit box likewise), so no order prunes a
//   primitive crossed before the nearest hit, and both walks end on the nearest crossing.
// - Which of two crossings at exactly the same distance wins depends on the order
//   (the later one is taken). A ray whose walk takes a hit at exactly its nearest hit's
//   distance (LeafOut::ties) is left to the single-ray walk.
// - That holds for intersectors whose crossing does not depend on the window's far end
//   and is taken exactly when it lies within it: the robust capsule (scalar and lanes)
//   and the robust curve intersectors, which ignore the window's far end in their search
//   (intersect_curve.h) and take their crossing by prim_take's t <= tmax. The triangle
//   compares a scaled distance; other primitives take the single-ray walk.
// A packet whose stack fills or whose steps run past the budget leaves every ray to
// the single-ray walk, which reports the fault if there is one.
#ifndef MASQ_KERNEL_PACKET_WALK_CPP_H
#define MASQ_KERNEL_PACKET_WALK_CPP_H
#if defined(MASQ_LANG_CPP)
#include "traverse.h"
#include <cstring>

KERNEL_NS_BEGIN

constexpr int kPacketRays = 8;

// Whether rays[0..kPacketRays) leave one point, bit for bit (a pinhole camera's): the
// rays the packet walk is for. Any other batch is traced ray by ray.
inline bool packet_common_origin(const Ray* rays) {
  for (int r = 1; r < kPacketRays; ++r)
    if (std::memcmp(rays[r].org, rays[0].org, sizeof rays[0].org) != 0) return false;
  return true;
}

// Whether this dispatch's rays may go in packets: closest hits without counters (the
// packet visits nodes in another order, so it would count other visits) in robust
// mode, on a scene of one BLAS of capsules, or of a TLAS of compact masquerade entries
// alone, of capsules and curves (KernelData::entry_packets).
FN_INLINED bool packet_walk_applies(KD_PARAM int tlas_root) {
  if (!MASQ_ROBUST || MASQ_ANY_HIT || MASQ_STATS || tlas_root < 0) return false;
  if (!MASQ_SINGLE_BLAS) return KD(entry_packets) != 0;
  if (!MASQ_HAVE_CAPSULES) return false;
  return KD(geoms)[KD(instances)[0].geom].type == MASQ_PRIM_CAPSULE;
}

// One ray's visit of a TLAS leaf of compact masquerade entries, as trace_closest makes
// it: the unit boxes four at a time (entry_boxes4: the scalar test's bits, whatever the
// leaf's size), each entry whose box the ray enters within the nearest hit so far then
// intersected, nearest box first (entries_nearest_first). rows: the leaf's entries
// decoded, where it holds at most four (the packet decodes a leaf once for all its
// rays), else null. Returns 1 when a hit it took ties the nearest hit (a hit, not the
// ray's end) at exactly its distance.
FN_INLINED int entry_leaf_closest(KD_PARAM const int* leaf_refs, int count, const simd::EntryRows4* rows,
                                  float t_bound, vec3 wo, vec3 wd, float tmin, Nearest& best) {
  int ties = 0;
  for (int j0 = 0; j0 < count; j0 += 4) {
    const int n = min(count - j0, 4);
    const simd::EntryBoxes4 eb = rows != nullptr ? simd::entry_boxes4(*rows, wo, wd, t_bound, true)
                                                 : simd::entry_boxes4(KD(masq_instances), leaf_refs + j0, n, wo, wd,
                                                                      t_bound, true);
    // Nearest box first, as the single-ray walk takes them; a tie sends the ray to that
    // walk, which takes a tied leaf in reference order (entry_leaf_nearest_first).
    if (entries_nearest_first(KD_ARG leaf_refs + j0, n, eb, wo, wd, tmin, best)) ties = 1;
  }
  return ties;
}

// Traces rays[0..kPacketRays) of a scene packet_walk_applies to, writing hits[r] for
// each ray it answers; returns the others as bits (1 << r), for trace_closest.
// kEntries: the scene's TLAS of masquerade entries (else its one BLAS of capsules).
template <bool kEntries>
FN_INLINED unsigned trace_packet_tree(KD_PARAM const Ray* rays, Hit* hits, int root, int budget) {
  constexpr int R = kPacketRays;
  constexpr unsigned all = (1u << R) - 1u;
  int only_geom = 0; // the one BLAS's geometry and scene instance (a TLAS of entries has no Instance)
  int only_inst = 0;
  if (!kEntries) {
    only_geom = KD(instances)[0].geom;
    only_inst = KD(instances)[0].scene_inst;
  }
  vec3 o[R], d[R], inv_d[R];
  float tmin[R];
  Nearest best[R];
  unsigned live = 0u;
  for (int r = 0; r < R; ++r) {
    o[r] = V3(rays[r].org);
    d[r] = V3(rays[r].dir);
    tmin[r] = rays[r].tmin;
    inv_d[r] = safe_rcp3(d[r]);
    best[r] = nearest_none(rays[r].tmax);
    if (ray_is_valid(o[r], d[r], tmin[r], rays[r].tmax)) live |= 1u << r;
  }
  unsigned ties = 0u;
  O4RayCache o4_cache[R];
  // A stack entry: a node, the rays that entered it, and each one's entry and exit
  // distances (the exit bounds an o4 BLAS node's padding, as in traverse_blas).
  int stack_node[MASQ_STACK_MAX];
  unsigned stack_rays[MASQ_STACK_MAX];
  float stack_t[MASQ_STACK_MAX][R];
  float stack_tf[MASQ_STACK_MAX][R];
  int sp = 1;
  stack_node[0] = root;
  stack_rays[0] = live;
  for (int r = 0; r < R; ++r) {
    stack_t[0][r] = tmin[r];
    stack_tf[0][r] = rays[r].tmax;
  }
  const int width = node_width();
  int steps = 0;
  while (sp > 0) {
    sp = sp - 1;
    const int node = stack_node[sp];
    if (MASQ_STEP_CHECK && ++steps > budget) return all;
    unsigned in = 0u;
    for (unsigned m = stack_rays[sp]; m != 0u; m &= m - 1u) {
      int r = __builtin_ctz(m);
      if (!(stack_t[sp][r] > best[r].t)) in |= 1u << r;
    }
    if (in == 0u) continue;
    // Each ray's test of the node's children, as its single-ray walk makes it (a TLAS
    // node is bounded by the nearest hit so far, as in trace_closest); a child's packet
    // entry distance is the nearest of the rays that enter it.
    WideHits wh[R];
    simd::SlotMasks hit[R];
    float packet_t[MASQ_WIDTH8];
    for (int i = 0; i < MASQ_WIDTH8; ++i) packet_t[i] = inf_();
    unsigned inner_any = 0u;
    for (unsigned m = in; m != 0u; m &= m - 1u) {
      int r = __builtin_ctz(m);
      if (kEntries)
        wh[r] = node_hits(KD_ARG node, o[r], d[r], inv_d[r], 0, VEC3(0.0f, 0.0f, 0.0f), tmin[r], best[r].t, best[r].t);
      else
        wh[r] = node_hits_cached(KD_ARG node, o[r], d[r], inv_d[r], 0, VEC3(0.0f, 0.0f, 0.0f), tmin[r], best[r].t,
                                 stack_tf[sp][r], o4_cache[r]);
      hit[r] = simd::slot_masks(wh[r].tnear, wh[r].count, width);
      inner_any |= hit[r].inner;
      for (unsigned c = hit[r].inner; c != 0u; c &= c - 1u) {
        int i = __builtin_ctz(c);
        packet_t[i] = min(packet_t[i], wh[r].tnear[i]);
      }
    }
    int inner[MASQ_WIDTH8];
    const int n_inner = simd::sorted_slots(packet_t, inner_any, inner);
    for (int k = 0; k < n_inner; ++k) prefetch_node(KD_ARG wh[__builtin_ctz(in)].child[inner[k]]);
    // A TLAS leaf's entries (and their curves) asked for, and decoded where they fit one
    // test, once for every ray that entered it.
    simd::EntryRows4 rows[kEntries ? MASQ_WIDTH8 : 1];
    if (kEntries) {
      const WideHits& any = wh[__builtin_ctz(in)]; // (the node's children: the same for every ray)
      unsigned leaves_any = 0u;
      for (unsigned m = in; m != 0u; m &= m - 1u) leaves_any |= hit[__builtin_ctz(m)].leaves;
      for (unsigned m = leaves_any; m != 0u; m &= m - 1u) {
        const int i = __builtin_ctz(m);
        const int* leaf_refs = KD(refs) + any.child[i];
        for (int j = 0; j < any.count[i]; ++j) {
          const int e = -1 - leaf_refs[j];
          __builtin_prefetch(KD(masq_instances) + e);
          if (KD(entry_curves) != nullptr) __builtin_prefetch(KD(entry_curves) + e);
        }
        if (any.count[i] <= 4) rows[i] = simd::entry_rows4(KD(masq_instances), leaf_refs, any.count[i]);
      }
    }
    // Each ray's hit leaves in its own entry order, as its single-ray walk takes them.
    for (unsigned m = in; m != 0u; m &= m - 1u) {
      int r = __builtin_ctz(m);
      int slot[MASQ_WIDTH8];
      int n = simd::sorted_slots(wh[r].tnear, hit[r].leaves, slot);
      if (n == 0) continue;
      if (kEntries) {
        int tied = 0;
        for (int k = 0; k < n; ++k) {
          const int i = slot[k];
          if (wh[r].tnear[i] > best[r].t) continue;
          tied |= entry_leaf_closest(KD_ARG KD(refs) + wh[r].child[i], wh[r].count[i],
                                     wh[r].count[i] <= 4 ? &rows[i] : nullptr, wh[r].tfar[i], o[r], d[r], tmin[r],
                                     best[r]);
        }
        if (tied != 0) ties |= 1u << r;
      } else {
        LeafOut lo = capsule_leaves(KD_ARG wh[r], slot, n, only_geom, only_inst, o[r], d[r], tmin[r], best[r]);
        best[r] = lo.nearest;
        if (lo.ties != 0) ties |= 1u << r;
      }
    }
    // The inner children pushed farthest first, each with the rays that entered it.
    for (int k = n_inner - 1; k >= 0; --k) {
      const int i = inner[k];
      if (sp >= MASQ_STACK_MAX) return all;
      unsigned entered = 0u;
      for (unsigned m = in; m != 0u; m &= m - 1u) {
        int r = __builtin_ctz(m);
        if ((hit[r].inner >> i) & 1u) {
          entered |= 1u << r;
          stack_t[sp][r] = wh[r].tnear[i];
          stack_tf[sp][r] = wh[r].tfar[i];
        }
      }
      stack_node[sp] = wh[__builtin_ctz(entered)].child[i];
      stack_rays[sp] = entered;
      sp = sp + 1;
    }
  }
  const unsigned answered = live & ~ties;
  for (unsigned m = answered; m != 0u; m &= m - 1u) {
    int r = __builtin_ctz(m);
    hits[r] = hit_from_nearest(KD_ARG best[r]);
  }
  return all & ~answered;
}

// The packet walk of the scene's tree (packet_walk_applies): rays[0..kPacketRays) in,
// hits[r] written for each ray it answers, the others returned as bits (1 << r).
FN_INLINED unsigned trace_packet_closest(KD_PARAM const Ray* rays, Hit* hits, int tlas_root, int budget) {
  if (MASQ_SINGLE_BLAS) return trace_packet_tree<false>(KD_ARG rays, hits, KD(instances)[0].blas_root, budget);
  return trace_packet_tree<true>(KD_ARG rays, hits, tlas_root, budget);
}

KERNEL_NS_END
#endif
#endif
