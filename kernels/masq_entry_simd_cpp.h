// cpu dialect only: the unit-box tests of a TLAS leaf's compact masquerade entries, up
// to four at once, one entry per lane, with the GCC/Clang vector extensions. Each lane
// performs the operations of affine_from_masq, affine_point, affine_vector and
// hit_unit_box_padded (robust mode) or hit_unit_box (fast mode) in the same order, so its
// entry and exit distances are bit-identical to the scalar test's; traverse.h then takes
// the lanes in reference order, each against the nearest hit so far, as the one-source
// loop decides entry by entry (or nearest box first where the order cannot change the
// hit: entry_leaf_nearest_first). Measured: docs/results.md (thirteenth round).
#ifndef MASQ_KERNEL_MASQ_ENTRY_SIMD_CPP_H
#define MASQ_KERNEL_MASQ_ENTRY_SIMD_CPP_H
#if defined(MASQ_LANG_CPP)
#include "box.h"
#include "masq_instance.h"
#include "slab_simd_cpp.h"
#include <bit>

namespace masq::kernel::simd {

// Lane j: entry j's slab interval (widened in robust mode). The ray enters the box where
// tn <= tf, tf >= tmin and tn <= the nearest hit so far (entry_in_box).
struct EntryBoxes4 {
  float tn[4];
  float tf[4];
};

inline bool entry_in_box(const EntryBoxes4& b, int j, float tmin, float tmax) {
  return b.tn[j] <= b.tf[j] && b.tf[j] >= tmin && b.tn[j] <= tmax;
}

// The lanes j < n whose boxes the ray enters within (tmin, tmax), into order[0..m) by
// entry distance (ties in lane order); returns m.
inline int entries_by_distance(const EntryBoxes4& b, int n, float tmin, float tmax, int order[4]) {
  int m = 0;
  for (int j = 0; j < n; ++j) {
    if (!entry_in_box(b, j, tmin, tmax)) continue;
    int k = m++;
    for (; k > 0 && b.tn[order[k - 1]] > b.tn[j]; --k) order[k] = order[k - 1];
    order[k] = j;
  }
  return m;
}

// glm's dot of a vec3: (x + y) + z of the products.
inline F4 dot_lanes(F4 ax, F4 ay, F4 az, float bx, float by, float bz) { return (ax * bx + ay * by) + az * bz; }

// Four entries' maps decoded (affine_from_masq's rows and translation, lane j: entry j):
// what the test below needs of them, the same for every ray.
struct EntryRows4 {
  F4 r00, r01, r02, r10, r11, r12, r20, r21, r22;
  F4 tx, ty, tz;
};

// The entries named by refs[0..n-1] (compact entries: ref = -1 - entry, n <= 4) decoded.
// Lanes past n repeat the first entry and are never read.
inline EntryRows4 entry_rows4(const MasqInstance* entries, const int* refs, int n) {
  I4 q01, q23, s01, s2;
  EntryRows4 m;
  for (int j = 0; j < 4; ++j) {
    const MasqInstance& c = entries[-1 - refs[j < n ? j : 0]];
    q01[j] = int(c.q01);
    q23[j] = int(c.q23);
    s01[j] = int(c.s01);
    s2[j] = int(c.s2_owner);
    m.tx[j] = c.t[0];
    m.ty[j] = c.t[1];
    m.tz[j] = c.t[2];
  }
  // word_half_i16 and word_half_bf16: the arithmetic shifts sign-extend a half as the
  // scalar's v >= 32768 ? v - 65536 : v does.
  const I4 x = (q01 << 16) >> 16, y = q01 >> 16, z = (q23 << 16) >> 16, w = q23 >> 16;
  const F4 sx = std::bit_cast<F4>(s01 << 16);
  const F4 sy = std::bit_cast<F4>(s01 & int(0xFFFF0000u));
  const F4 sz = std::bit_cast<F4>(s2 & int(0xFFFF0000u));
  const I4 xx = x * x, yy = y * y, zz = z * z, ww = w * w;
  const I4 xy = x * y, xz = x * z, yz = y * z, wx = w * x, wy = w * y, wz = w * z;
  auto f = [](I4 v) { return __builtin_convertvector(v, F4); };
  // affine_from_masq's rows.
  m.r00 = f(ww + xx - yy - zz) * sx, m.r01 = f(2 * (xy + wz)) * sx, m.r02 = f(2 * (xz - wy)) * sx;
  m.r10 = f(2 * (xy - wz)) * sy, m.r11 = f(ww - xx + yy - zz) * sy, m.r12 = f(2 * (yz + wx)) * sy;
  m.r20 = f(2 * (xz + wy)) * sz, m.r21 = f(2 * (yz - wx)) * sz, m.r22 = f(ww - xx - yy + zz) * sz;
  return m;
}

// The decoded entries m tested with the world ray (wo, wd); t_bound: the leaf's exit
// distance (hit_unit_box_padded). robust: MASQ_ROBUST (a variant's constant, or read at
// run time by the cpu's default unit).
inline EntryBoxes4 entry_boxes4(const EntryRows4& m, glm::vec3 wo, glm::vec3 wd, float t_bound, bool robust) {
  const F4 r00 = m.r00, r01 = m.r01, r02 = m.r02, r10 = m.r10, r11 = m.r11, r12 = m.r12;
  const F4 r20 = m.r20, r21 = m.r21, r22 = m.r22, tx = m.tx, ty = m.ty, tz = m.tz;
  // affine_point and affine_vector.
  const F4 ox = dot_lanes(r00, r01, r02, wo.x, wo.y, wo.z) + tx;
  const F4 oy = dot_lanes(r10, r11, r12, wo.x, wo.y, wo.z) + ty;
  const F4 oz = dot_lanes(r20, r21, r22, wo.x, wo.y, wo.z) + tz;
  const F4 dx = dot_lanes(r00, r01, r02, wd.x, wd.y, wd.z);
  const F4 dy = dot_lanes(r10, r11, r12, wd.x, wd.y, wd.z);
  const F4 dz = dot_lanes(r20, r21, r22, wd.x, wd.y, wd.z);
  F4 ex = 1.0f - F4{}, ey = ex, ez = ex;
  if (robust) {
    // transform_error (origin term, direction term, their sum at t_bound), then the
    // bounds rounded outward by one more relative step (hit_unit_box_padded).
    const glm::vec3 ao = glm::abs(wo), ad = glm::abs(wd);
    const F4 a00 = vabs(r00), a01 = vabs(r01), a02 = vabs(r02);
    const F4 a10 = vabs(r10), a11 = vabs(r11), a12 = vabs(r12);
    const F4 a20 = vabs(r20), a21 = vabs(r21), a22 = vabs(r22);
    const float tb = std::fabs(t_bound) * MASQ_GAMMA3;
    const F4 px = MASQ_GAMMA4 * (dot_lanes(a00, a01, a02, ao.x, ao.y, ao.z) + vabs(tx)) +
                  tb * dot_lanes(a00, a01, a02, ad.x, ad.y, ad.z);
    const F4 py = MASQ_GAMMA4 * (dot_lanes(a10, a11, a12, ao.x, ao.y, ao.z) + vabs(ty)) +
                  tb * dot_lanes(a10, a11, a12, ad.x, ad.y, ad.z);
    const F4 pz = MASQ_GAMMA4 * (dot_lanes(a20, a21, a22, ao.x, ao.y, ao.z) + vabs(tz)) +
                  tb * dot_lanes(a20, a21, a22, ad.x, ad.y, ad.z);
    ex = (1.0f + px) * (1.0f + 2.0f * MASQ_U);
    ey = (1.0f + py) * (1.0f + 2.0f * MASQ_U);
    ez = (1.0f + pz) * (1.0f + 2.0f * MASQ_U);
  }
  // safe_rcp3 and the slab test.
  const F4 big = 1e30f - F4{};
  const F4 ix = dx != 0.0f ? 1.0f / dx : big, iy = dy != 0.0f ? 1.0f / dy : big, iz = dz != 0.0f ? 1.0f / dz : big;
  const F4 tx0 = (-ex - ox) * ix, tx1 = (ex - ox) * ix;
  const F4 ty0 = (-ey - oy) * iy, ty1 = (ey - oy) * iy;
  const F4 tz0 = (-ez - oz) * iz, tz1 = (ez - oz) * iz;
  F4 tn = vmax(vmin(tx0, tx1), vmax(vmin(ty0, ty1), vmin(tz0, tz1)));
  F4 tf = vmin(vmax(tx0, tx1), vmin(vmax(ty0, ty1), vmax(tz0, tz1)));
  if (robust) {
    tn = tn - vabs(tn) * MASQ_BOX_WIDEN;
    tf = tf + vabs(tf) * MASQ_BOX_WIDEN;
  }
  EntryBoxes4 out;
  std::memcpy(out.tn, &tn, sizeof tn);
  std::memcpy(out.tf, &tf, sizeof tf);
  return out;
}

// The entries named by refs[0..n-1] (n <= 4), decoded and tested.
inline EntryBoxes4 entry_boxes4(const MasqInstance* entries, const int* refs, int n, glm::vec3 wo, glm::vec3 wd,
                                float t_bound, bool robust) {
  return entry_boxes4(entry_rows4(entries, refs, n), wo, wd, t_bound, robust);
}

} // namespace masq::kernel::simd

#endif
#endif
