// cpu dialect only: the roving sieve (curve_roving.h, step 0) on its eight pieces at once,
// one piece per lane, with the GCC/Clang vector extensions. Every lane performs the
// operations of curve_piece_end and curve_sieve_keeps in the same order (selects for the
// branches), so each lane's verdict is the scalar loop's bit for bit, and the call's
// outcome the same on every backend (tests/test_curve_sieve.cpp).
#ifndef MASQ_KERNEL_CURVE_SIEVE_SIMD_CPP_H
#define MASQ_KERNEL_CURVE_SIEVE_SIMD_CPP_H
#if defined(MASQ_LANG_CPP)
#include "capsule_simd_cpp.h"

namespace masq::kernel::simd {

// One cut per lane: the curve's point and one piece's handle there, curve_piece_end's
// de Casteljau steps per coordinate.
struct SieveEnds8 {
  F8 px, py, pz, hx, hy, hz;
};

inline void curve_sieve_end8(float b0, float b1, float b2, float b3, F8 s, float h, F8& p, F8& dh) {
  F8 t = 1.0f - s;
  F8 a = t * b0 + s * b1, b = t * b1 + s * b2, c = t * b2 + s * b3;
  F8 ab = t * a + s * b, bc = t * b + s * c;
  p = t * ab + s * bc;
  dh = h * (bc - ab);
}

inline SieveEnds8 curve_sieve_ends8(const glm::vec3 b[4], F8 s, float h) {
  SieveEnds8 e;
  curve_sieve_end8(b[0].x, b[1].x, b[2].x, b[3].x, s, h, e.px, e.hx);
  curve_sieve_end8(b[0].y, b[1].y, b[2].y, b[3].y, s, h, e.py, e.hy);
  curve_sieve_end8(b[0].z, b[1].z, b[2].z, b[3].z, s, h, e.pz, e.hz);
  return e;
}

// Bit k: the sieve keeps piece k of eight (curve_sieve_keeps on its control points).
inline unsigned curve_sieve_mask8(const glm::vec3 b[4], float rr, float zlo) {
  const float h = 1.0f / 8.0f;
  const F8 k = {0.0f, 1.0f, 2.0f, 3.0f, 4.0f, 5.0f, 6.0f, 7.0f};
  SieveEnds8 lo = curve_sieve_ends8(b, k * h, h);
  SieveEnds8 hi = curve_sieve_ends8(b, (k + 1.0f) * h, h);
  F8 q0x = lo.px, q0y = lo.py, q0z = lo.pz;
  F8 q1x = lo.px + lo.hx, q1y = lo.py + lo.hy, q1z = lo.pz + lo.hz;
  F8 q2x = hi.px - hi.hx, q2y = hi.py - hi.hy, q2z = hi.pz - hi.hz;
  F8 q3x = hi.px, q3y = hi.py, q3z = hi.pz;
  F8 cx = q3x - q0x, cy = q3y - q0y, cz = q3z - q0z;
  F8 g1x = q1x - (q0x + cx * (1.0f / 3.0f)), g1y = q1y - (q0y + cy * (1.0f / 3.0f));
  F8 g1z = q1z - (q0z + cz * (1.0f / 3.0f));
  F8 g2x = q2x - (q3x - cx * (1.0f / 3.0f)), g2y = q2y - (q3y - cy * (1.0f / 3.0f));
  F8 g2z = q2z - (q3z - cz * (1.0f / 3.0f));
  F8 cap = rr + vsqrt(vmax((g1x * g1x + g1y * g1y) + g1z * g1z, (g2x * g2x + g2y * g2y) + g2z * g2z));
  F8 cap2 = cap * cap;
  const F8 zero = splat_as<F8>(0.0f);
  F8 zout = splat_as<F8>(-std::numeric_limits<float>::infinity());
  F8 da = cap2 - (q0x * q0x + q0y * q0y);
  zout = da >= 0.0f ? q0z + vsqrt(vmax(da, zero)) : zout;
  F8 db = cap2 - (q3x * q3x + q3y * q3y);
  zout = db >= 0.0f ? vmax(zout, q3z + vsqrt(vmax(db, zero))) : zout;
  F8 aa = cx * cx + cy * cy;
  F8 ee = aa + cz * cz;
  F8 cr = q0x * cy - q0y * cx;
  F8 dl = cap2 - (cr * cr) / aa;
  F8 us = -(q0x * cx + q0y * cy) / aa;
  F8 hw = vsqrt(vmax((dl * ee) / aa, zero));
  F8 u = us + (hw * cz) / ee;
  I8 lateral = (aa > 1e-12f * ee) & (dl >= 0.0f) & (u >= 0.0f) & (u <= 1.0f);
  zout = lateral ? vmax(zout, (q0z + us * cz) + hw) : zout;
  I8 keep = zout >= zlo;
  unsigned m = 0;
  for (int i = 0; i < 8; ++i) m |= keep[i] != 0 ? 1u << i : 0u;
  return m;
}

} // namespace masq::kernel::simd
#endif
#endif
