// cpu only: eight camera rays walked through one BLAS together (a packet), each with the
// node test, leaf tests and nearest-hit rule of traverse_blas, in a shared node order.
// A pinhole camera's neighbouring rays mostly enter the same nodes: the packet fetches,
// orders, pushes and pops each node once for all of them instead of once per ray.
//
// Why every ray gets traverse_blas's answer, bit for bit (docs/kernels.md, "Packets"):
// - The packet takes a node's children in the order of their nearest entry over the
//   packet, not each ray's own, so a ray may meet its primitives in another order. In
//   robust mode a box holds every crossing of what lies in it (the boxes are padded,
//   the slab test widened), so no order prunes a primitive crossed before the nearest
//   hit, and both walks end on the nearest crossing.
// - Which of two crossings at exactly the same distance wins depends on the order
//   (the later one is taken). A ray whose walk takes a hit at exactly its nearest hit's
//   distance (LeafOut::ties) is left to traverse_blas.
// - That holds for intersectors whose crossing does not depend on the window's far end
//   and is taken exactly when it lies within it: the robust capsule (scalar and lanes).
//   The triangle compares a scaled distance, the curves search their window, so other
//   primitives take the single-ray walk.
// A packet whose stack fills or whose steps run past the budget leaves every ray to
// traverse_blas, which reports the fault if there is one.
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
// mode, on a scene of one BLAS of capsules.
FN_INLINED bool packet_walk_applies(KD_PARAM int tlas_root) {
  if (!MASQ_ROBUST || MASQ_ANY_HIT || MASQ_STATS || !MASQ_SINGLE_BLAS || !MASQ_HAVE_CAPSULES || tlas_root < 0)
    return false;
  return KD(geoms)[KD(instances)[0].geom].type == MASQ_PRIM_CAPSULE;
}

// Traces rays[0..kPacketRays) of a scene packet_walk_applies to, writing hits[r] for
// each ray it answers; returns the others as bits (1 << r), for trace_closest.
FN_INLINED unsigned trace_packet_closest(KD_PARAM const Ray* rays, Hit* hits, int budget) {
  constexpr int R = kPacketRays;
  constexpr unsigned all = (1u << R) - 1u;
  const Instance only = KD(instances)[0];
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
  // distances (the exit bounds an o4 node's padding, as in traverse_blas).
  int stack_node[MASQ_STACK_MAX];
  unsigned stack_rays[MASQ_STACK_MAX];
  float stack_t[MASQ_STACK_MAX][R];
  float stack_tf[MASQ_STACK_MAX][R];
  int sp = 1;
  stack_node[0] = only.blas_root;
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
    // Each ray's test of the node's children, as traverse_blas makes it; a child's
    // packet entry distance is the nearest of the rays that enter it.
    WideHits wh[R];
    simd::SlotMasks hit[R];
    float packet_t[MASQ_WIDTH8];
    for (int i = 0; i < MASQ_WIDTH8; ++i) packet_t[i] = inf_();
    unsigned inner_any = 0u;
    for (unsigned m = in; m != 0u; m &= m - 1u) {
      int r = __builtin_ctz(m);
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
    // Each ray's hit leaves in its own entry order, as traverse_blas takes them.
    for (unsigned m = in; m != 0u; m &= m - 1u) {
      int r = __builtin_ctz(m);
      int slot[MASQ_WIDTH8];
      int n = simd::sorted_slots(wh[r].tnear, hit[r].leaves, slot);
      if (n == 0) continue;
      LeafOut lo = capsule_leaves(KD_ARG wh[r], slot, n, only.geom, only.scene_inst, o[r], d[r], tmin[r], best[r]);
      best[r] = lo.nearest;
      if (lo.ties != 0) ties |= 1u << r;
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

KERNEL_NS_END
#endif
#endif
