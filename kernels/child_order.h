// The order a node's hit children are visited in: by entry distance, nearest first,
// ties in slot order (so every backend visits the same nodes in the same order).
// Occlusion queries in a TLAS of masquerade entries take another order,
// order_children_occlusion below.
#ifndef MASQ_KERNEL_CHILD_ORDER_H
#define MASQ_KERNEL_CHILD_ORDER_H
#include "box.h"

KERNEL_NS_BEGIN

// The hit slots (tnear finite) in visit order: slot[0..n-1]. GLSL also fills
// slot[n..7] with the missed slots.
STRUCT_BEGIN(ChildOrder)
  int slot[MASQ_WIDTH8];
  int n;
STRUCT_END(ChildOrder)

#if defined(MASQ_LANG_GLSL)
// Vulkan: a sorting network over (tnear, slot). lavapipe runs eight rays in the lanes of
// one SIMD register, so an insertion sort's data-dependent loop and its stores at each
// lane's own index cost every lane the slowest lane's work, through per-lane memory;
// the network is the same compare-exchanges at fixed slots for every lane, in registers.
// On lavapipe it traced 1.2-1.7x faster (docs/kernels.md, "Child order on Vulkan");
// PoCL, which vectorises the same way, ran it 0.86x, so OpenCL and C++ keep the
// insertion sort. The keys travel with the slots (key[a] is always tnear[slot[a]]), so
// every array access of the network is at a fixed index: a GPU keeps them in registers
// where reading tnear[slot[a]] would index a per-thread array by a run-time value.
STRUCT_BEGIN(OrderKeys)
  float key[MASQ_WIDTH8];
  int slot[MASQ_WIDTH8];
STRUCT_END(OrderKeys)

FN OrderKeys order_cswap(OrderKeys o, int a, int b) {
  float ta = o.key[a];
  float tb = o.key[b];
  int sa = o.slot[a];
  int sb = o.slot[b];
  bool swap = ta > tb || (ta == tb && sa > sb);
  o.key[a] = swap ? tb : ta;
  o.key[b] = swap ? ta : tb;
  o.slot[a] = swap ? sb : sa;
  o.slot[b] = swap ? sa : sb;
  return o;
}

FN ChildOrder order_children(WideHits wh, int width) {
  OrderKeys o;
  ChildOrder co;
  co.n = 0;
  for (int i = 0; i < MASQ_WIDTH8; ++i) {
    o.key[i] = i < width ? wh.tnear[i] : inf_(); // (slots beyond the width are missed anyway)
    o.slot[i] = i;
    co.n = co.n + (o.key[i] == inf_() ? 0 : 1);
  }
  if (width == MASQ_WIDTH) {
    o = order_cswap(o, 0, 1);
    o = order_cswap(o, 2, 3);
    o = order_cswap(o, 0, 2);
    o = order_cswap(o, 1, 3);
    o = order_cswap(o, 1, 2);
  } else {
    // Knuth's 19 comparators for eight keys (TAOCP vol. 3, 5.3.4).
    o = order_cswap(o, 0, 2);
    o = order_cswap(o, 1, 3);
    o = order_cswap(o, 4, 6);
    o = order_cswap(o, 5, 7);
    o = order_cswap(o, 0, 4);
    o = order_cswap(o, 1, 5);
    o = order_cswap(o, 2, 6);
    o = order_cswap(o, 3, 7);
    o = order_cswap(o, 0, 1);
    o = order_cswap(o, 2, 3);
    o = order_cswap(o, 4, 5);
    o = order_cswap(o, 6, 7);
    o = order_cswap(o, 2, 4);
    o = order_cswap(o, 3, 5);
    o = order_cswap(o, 1, 4);
    o = order_cswap(o, 3, 6);
    o = order_cswap(o, 1, 2);
    o = order_cswap(o, 3, 4);
    o = order_cswap(o, 5, 6);
  }
  for (int i = 0; i < MASQ_WIDTH8; ++i) co.slot[i] = o.slot[i];
  return co;
}
#else
// OpenCL and C++: insertion sort on slot indices (up to 8), stable. OpenCL visits in
// this order; C++ keeps it as the reference its bitmask form below is tested against.
FN ChildOrder order_children_loop(WideHits wh, int width) {
  ChildOrder co;
  co.n = 0;
  for (int i = 0; i < width; ++i) {
    if (wh.tnear[i] == inf_()) continue;
    int j = co.n;
    while (j > 0 && wh.tnear[co.slot[j - 1]] > wh.tnear[i]) {
      co.slot[j] = co.slot[j - 1];
      --j;
    }
    co.slot[j] = i;
    co.n = co.n + 1;
  }
  return co;
}

#if defined(MASQ_LANG_CPP)
// C++: the hit slots as a bitmask sorted by slab_simd_cpp.h's sorted_slots, the loop's
// order without its pass over every slot. The hits are read in place: a copy by value
// was read back wider than it was stored (a failed store forward on every TLAS visit,
// perf on the masquerade's rays).
FN ChildOrder order_children(const WideHits& wh, int width) {
  ChildOrder co;
  co.n = simd::sorted_slots(wh.tnear, simd::hit_slots(wh.tnear, width), co.slot);
  return co;
}
#else
FN ChildOrder order_children(WideHits wh, int width) { return order_children_loop(wh, width); }
#endif
#endif

// Occlusion queries (MASQ_ANY_HIT) end at any occluder, so their order only decides how
// soon they meet one. In a TLAS of masquerade entries (MASQ_TLAS_STARTS_LAST,
// kernels/traverse.h's order_tlas_children): the children the ray enters after tmin
// first, then those it starts in (entry at tmin: the node tests clamp a hit's entry
// there), each group in slot order. A secondary ray starts on a surface; there a box is
// one primitive's, so the boxes around the origin hold the primitive the ray starts on
// and its neighbours, which it mostly leaves without a hit. Taken nearest first, they
// were all tested before any box farther along the ray (bear curve shadow rays: 1.73
// curve calls a ray nearest first, 1.46 in this order; docs/results.md, eleventh round).
// A BLAS's or a cluster's box around the origin holds the likely occluders as well (the
// default bundle's shadow rays: 5-13% slower in this order), so they keep the nearest-
// first order, unless the structure asks for this one over a BLAS node's inner children
// (MASQ_BLAS_STARTS_LAST, AccelOptions::blas_occlusion): over hair in one BLAS a shadow
// ray mostly leaves the subtrees around its origin too (the bear's capsule shadow rays:
// 8% faster), while the bundle's and clusters' lose 1-3% (docs/results.md, twelfth
// round), so the peers pilot tries both. As keys for the sorts above, ties in slot
// order: 0 (entered after tmin), 1 (started in), +inf (missed).
FN float occlusion_key(float tnear, float tmin) {
  return tnear == inf_() ? inf_() : (tnear <= tmin ? 1.0f : 0.0f);
}

// The hit slots in an occlusion query's order (the cpu's traversal takes the same order
// from simd::occlusion_slots).
FN ChildOrder order_children_occlusion(WideHits wh, int width, float tmin) {
  for (int i = 0; i < MASQ_WIDTH8; ++i) wh.tnear[i] = occlusion_key(wh.tnear[i], tmin); // (a copy)
  return order_children(wh, width);
}

KERNEL_NS_END
#endif
