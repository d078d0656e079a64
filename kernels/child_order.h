// The order a node's hit children are visited in: by entry distance, nearest first,
// ties in slot order (so every backend visits the same nodes in the same order).
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
// insertion sort.
FN ChildOrder order_cswap(ChildOrder co, float tnear[MASQ_WIDTH8], int a, int b) {
  int sa = co.slot[a];
  int sb = co.slot[b];
  float ta = tnear[sa];
  float tb = tnear[sb];
  bool swap = ta > tb || (ta == tb && sa > sb);
  co.slot[a] = swap ? sb : sa;
  co.slot[b] = swap ? sa : sb;
  return co;
}

FN ChildOrder order_children(WideHits wh, int width) {
  ChildOrder co;
  float t[MASQ_WIDTH8];
  co.n = 0;
  for (int i = 0; i < MASQ_WIDTH8; ++i) {
    t[i] = i < width ? wh.tnear[i] : inf_(); // slots beyond the width are not set
    co.slot[i] = i;
    co.n = co.n + (t[i] == inf_() ? 0 : 1);
  }
  if (width == MASQ_WIDTH) {
    co = order_cswap(co, t, 0, 1);
    co = order_cswap(co, t, 2, 3);
    co = order_cswap(co, t, 0, 2);
    co = order_cswap(co, t, 1, 3);
    co = order_cswap(co, t, 1, 2);
    return co;
  }
  // Knuth's 19 comparators for eight keys (TAOCP vol. 3, 5.3.4).
  co = order_cswap(co, t, 0, 2);
  co = order_cswap(co, t, 1, 3);
  co = order_cswap(co, t, 4, 6);
  co = order_cswap(co, t, 5, 7);
  co = order_cswap(co, t, 0, 4);
  co = order_cswap(co, t, 1, 5);
  co = order_cswap(co, t, 2, 6);
  co = order_cswap(co, t, 3, 7);
  co = order_cswap(co, t, 0, 1);
  co = order_cswap(co, t, 2, 3);
  co = order_cswap(co, t, 4, 5);
  co = order_cswap(co, t, 6, 7);
  co = order_cswap(co, t, 2, 4);
  co = order_cswap(co, t, 3, 5);
  co = order_cswap(co, t, 1, 4);
  co = order_cswap(co, t, 3, 6);
  co = order_cswap(co, t, 1, 2);
  co = order_cswap(co, t, 3, 4);
  co = order_cswap(co, t, 5, 6);
  return co;
}
#else
// OpenCL and C++: insertion sort on slot indices (up to 8), stable.
FN ChildOrder order_children(WideHits wh, int width) {
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
#endif

KERNEL_NS_END
#endif
