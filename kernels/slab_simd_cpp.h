// cpu dialect only: the wide node's slab test on all of its slots at once, with the
// GCC/Clang vector extensions (SSE on x86-64 without any -march flag, NEON on arm64).
// It performs the same operations in the same order as the one-source loops of
// intersect_wide_node, intersect_wide_node_padded and slab_hit, so every backend
// still gets bit-identical entry distances; the loops stay the GLSL and OpenCL form
// (PoCL vectorises across work-items instead). Measured: docs/kernels.md.
#ifndef MASQ_KERNEL_SLAB_SIMD_CPP_H
#define MASQ_KERNEL_SLAB_SIMD_CPP_H
#if defined(MASQ_LANG_CPP)
#include "math.h"
#include <bit>
#include <cstdint>
#include <cstring>
#include <limits>

namespace masq::kernel::simd {

typedef float F4 __attribute__((vector_size(16)));
typedef int I4 __attribute__((vector_size(16)));
// Eight lanes: one AVX register where the build machine has AVX (-march=native), else
// two SSE registers; the same operations lane by lane either way.
typedef float F8 __attribute__((vector_size(32)));
typedef int I8 __attribute__((vector_size(32)));

template <class V> inline V load(const void* p) {
  V v;
  std::memcpy(&v, p, sizeof v);
  return v;
}
// glm::min and glm::max exactly: min(a, b) = b < a ? b : a; max(a, b) = a < b ? b : a.
template <class F> inline F vmin(F a, F b) { return b < a ? b : a; }
template <class F> inline F vmax(F a, F b) { return a < b ? b : a; }
// fabs: the sign bit cleared (a < 0 ? -a : a would keep -0, and -0 + 0 is not -0 - 0).
inline F4 vabs(F4 a) { return std::bit_cast<F4>(std::bit_cast<I4>(a) & 0x7fffffff); }
inline F8 vabs(F8 a) { return std::bit_cast<F8>(std::bit_cast<I8>(a) & 0x7fffffff); }

// Child boxes as planes: lane i holds slot i's bounds (four or eight slots).
template <class F> struct PlanesN {
  F lx, hx, ly, hy, lz, hz;
};
using Planes4 = PlanesN<F4>;
using Planes8 = PlanesN<F8>;

// Writes tnear (entry distance clamped to tmin, or +inf when the slot is not live or
// missed within [tmin, tmax]) and tfar (unspecified for slots that are not live, which
// nothing reads) of four or eight slots. padded != 0 grows each box by pad and 2u of
// each bound's magnitude, as intersect_wide_node_padded and slab_hit do.
template <class F, class I>
inline void slab_hitsv(PlanesN<F> p, I live, glm::vec3 o, glm::vec3 inv_d, int padded, glm::vec3 pad, float tmin,
                       float tmax, float* tnear, float* tfar) {
  const float two_u = 2.0f * MASQ_U;
  if (padded != 0) {
    p.lx = p.lx - (pad.x + vabs(p.lx) * two_u);
    p.hx = p.hx + (pad.x + vabs(p.hx) * two_u);
    p.ly = p.ly - (pad.y + vabs(p.ly) * two_u);
    p.hy = p.hy + (pad.y + vabs(p.hy) * two_u);
    p.lz = p.lz - (pad.z + vabs(p.lz) * two_u);
    p.hz = p.hz + (pad.z + vabs(p.hz) * two_u);
  }
  F tx0 = (p.lx - o.x) * inv_d.x, tx1 = (p.hx - o.x) * inv_d.x;
  F ty0 = (p.ly - o.y) * inv_d.y, ty1 = (p.hy - o.y) * inv_d.y;
  F tz0 = (p.lz - o.z) * inv_d.z, tz1 = (p.hz - o.z) * inv_d.z;
  F a = vmax(vmin(tx0, tx1), vmax(vmin(ty0, ty1), vmin(tz0, tz1)));
  F b = vmin(vmax(tx0, tx1), vmin(vmax(ty0, ty1), vmax(tz0, tz1)));
  F tn = a - vabs(a) * MASQ_BOX_WIDEN;
  F tf = b + vabs(b) * MASQ_BOX_WIDEN;
  F lo_t = tmin - F{}; // tmin in every lane (x - 0 is x, signed zeros included)
  F inf = std::numeric_limits<float>::infinity() - F{};
  I hit = live & (tn <= tf) & (tf >= tmin) & (tn <= tmax);
  F near = hit ? vmax(tn, lo_t) : inf;
  std::memcpy(tnear, &near, sizeof near);
  std::memcpy(tfar, &tf, sizeof tf);
}
inline void slab_hits4v(Planes4 p, I4 live, glm::vec3 o, glm::vec3 inv_d, int padded, glm::vec3 pad, float tmin,
                        float tmax, float* tnear, float* tfar) {
  slab_hitsv(p, live, o, inv_d, padded, pad, tmin, tmax, tnear, tfar);
}

// Float boxes stored as SoA rows (slot i at lo_x[i], ...); count[i] < 0 marks an empty
// slot. w4 and o4 nodes call it once; q8 tests its eight slots as two groups of four
// through slab_hits4v, w8 all eight at once through slab_hits8 below.
inline void slab_hits4(const float* lo_x, const float* hi_x, const float* lo_y, const float* hi_y, const float* lo_z,
                       const float* hi_z, const int* count, glm::vec3 o, glm::vec3 inv_d, int padded, glm::vec3 pad,
                       float tmin, float tmax, float* tnear, float* tfar) {
  Planes4 p{load<F4>(lo_x), load<F4>(hi_x), load<F4>(lo_y), load<F4>(hi_y), load<F4>(lo_z), load<F4>(hi_z)};
  slab_hits4v(p, load<I4>(count) >= 0, o, inv_d, padded, pad, tmin, tmax, tnear, tfar);
}
// The same for eight slots at once (w8 nodes).
inline void slab_hits8(const float* lo_x, const float* hi_x, const float* lo_y, const float* hi_y, const float* lo_z,
                       const float* hi_z, const int* count, glm::vec3 o, glm::vec3 inv_d, int padded, glm::vec3 pad,
                       float tmin, float tmax, float* tnear, float* tfar) {
  Planes8 p{load<F8>(lo_x), load<F8>(hi_x), load<F8>(lo_y), load<F8>(hi_y), load<F8>(lo_z), load<F8>(hi_z)};
  slab_hitsv(p, load<I8>(count) >= 0, o, inv_d, padded, pad, tmin, tmax, tnear, tfar);
}

// q8 planes of four slots: the word holds their 8-bit grid coordinates (byte j: slot j);
// each decodes as origin + q * step, the order of hits_q8's loop.
inline F4 dequantise4(std::uint32_t word, float origin, float step) {
  I4 q = (std::bit_cast<int>(word) - I4{}) >> I4{0, 8, 16, 24} & 255;
  return origin + __builtin_convertvector(q, F4) * step;
}

// The hit slots of a node test (entry distance not +inf) that are leaves (count > 0)
// and inner children (count == 0), one bit per slot.
struct SlotMasks {
  unsigned leaves;
  unsigned inner;
};
// One bit per lane: the lane's sign bit, i.e. set where a vector comparison is true.
inline unsigned lane_bits(I4 m) {
#if defined(__SSE__)
  return unsigned(__builtin_ia32_movmskps(std::bit_cast<F4>(m)));
#else
  unsigned b = 0u;
  for (int i = 0; i < 4; ++i) b |= unsigned(m[i] != 0) << i;
  return b;
#endif
}
// Both read the rows the node test has just stored, one compare and one movemask per
// four slots (a scalar loop over the slots cost about a tenth of a BVH walk's time,
// perf on the bear's shadow rays).
// The slots whose entry distance is not +inf (those the node test hit).
inline unsigned hit_slots(const float* tnear, int width) {
  const F4 inf = std::numeric_limits<float>::infinity() - F4{};
  unsigned m = 0u;
  for (int g = 0; g < width; g += 4) m |= lane_bits(load<F4>(tnear + g) != inf) << g;
  return m;
}
inline SlotMasks slot_masks(const float* tnear, const int* count, int width) {
  unsigned hit = hit_slots(tnear, width), leaf = 0u, inner = 0u;
  for (int g = 0; g < width; g += 4) {
    I4 c = load<I4>(count + g);
    leaf |= lane_bits(c > 0) << g;
    inner |= lane_bits(c == 0) << g;
  }
  return SlotMasks{hit & leaf, hit & inner};
}

// The slots whose entry distance is at most tmin: the boxes the ray starts in (the node
// tests clamp a hit's entry to tmin).
inline unsigned start_slots(const float* tnear, float tmin, int width) {
  const F4 t0 = tmin - F4{};
  unsigned m = 0u;
  for (int g = 0; g < width; g += 4) m |= lane_bits(load<F4>(tnear + g) <= t0) << g;
  return m;
}

// The slots of `mask` in an occlusion query's order (child_order.h,
// order_children_occlusion): those the ray enters after tmin, then those it starts in
// (`starts`), each in slot order. No comparisons between slots: two bit scans.
inline int occlusion_slots(unsigned mask, unsigned starts, int* out) {
  int n = 0;
  for (unsigned m = mask & ~starts; m != 0u; m &= m - 1u) out[n++] = __builtin_ctz(m);
  for (unsigned m = mask & starts; m != 0u; m &= m - 1u) out[n++] = __builtin_ctz(m);
  return n;
}

// The slots of `mask` in order of entry distance, ties in slot order: the order of
// order_children's stable insertion sort. One or two slots (most visits) take no loop.
inline int sorted_slots(const float* tnear, unsigned mask, int* out) {
  if (mask == 0u) return 0;
  int a = __builtin_ctz(mask);
  mask &= mask - 1u;
  out[0] = a;
  if (mask == 0u) return 1;
  int b = __builtin_ctz(mask);
  mask &= mask - 1u;
  bool swap = tnear[b] < tnear[a];
  out[0] = swap ? b : a;
  out[1] = swap ? a : b;
  int n = 2;
  while (mask != 0u) {
    int i = __builtin_ctz(mask);
    mask &= mask - 1u;
    int j = n;
    while (j > 0 && tnear[out[j - 1]] > tnear[i]) {
      out[j] = out[j - 1];
      --j;
    }
    out[j] = i;
    ++n;
  }
  return n;
}

} // namespace masq::kernel::simd
#endif
#endif
