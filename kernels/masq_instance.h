// Decoding a compact masquerade entry (MasqInstance, kernels/layout.h) into the affine
// world -> unit-box map the traversal tests, exactly as the host's encoder
// (bvh/nodes/compact_instance.cpp) assumes: N = |q|^2 R(q) in exact integer arithmetic, then
// per entry one int -> float conversion and one product with the row's scale.
#ifndef MASQ_KERNEL_MASQ_INSTANCE_H
#define MASQ_KERNEL_MASQ_INSTANCE_H
#include "math.h"

KERNEL_NS_BEGIN

// The 16-bit two's complement integer in the low (hi == 0) or high half of a word.
FN int word_half_i16(uint w, int hi) {
  int v = u2i_(hi != 0 ? (w >> 16) : (w & 0xFFFFu));
  return v >= 32768 ? v - 65536 : v;
}

// The bfloat16 in the low (hi == 0) or high half of a word, as the fp32 it truncates.
FN float word_half_bf16(uint w, int hi) { return as_float_(hi != 0 ? (w & 0xFFFF0000u) : (w << 16)); }

FN int masq_owner_index(MasqInstance c) { return u2i_(c.s2_owner & MASQ_OWNER_MASK); }

// M = diag(sigma) N^T with N the homogeneous rotation matrix of q (a rotation times
// |q|^2 for any q != 0). Every N_ij is an integer of magnitude <= |q|^2 < 2^31 (the
// host keeps |q|^2 below 2^31), so the integer products and sums are exact.
FN Affine affine_from_masq(MasqInstance c) {
  int x = word_half_i16(c.q01, 0);
  int y = word_half_i16(c.q01, 1);
  int z = word_half_i16(c.q23, 0);
  int w = word_half_i16(c.q23, 1);
  int xx = x * x;
  int yy = y * y;
  int zz = z * z;
  int ww = w * w;
  int xy = x * y;
  int xz = x * z;
  int yz = y * z;
  int wx = w * x;
  int wy = w * y;
  int wz = w * z;
  float sx = word_half_bf16(c.s01, 0);
  float sy = word_half_bf16(c.s01, 1);
  float sz = word_half_bf16(c.s2_owner, 1);
  Affine m;
  // Row i of M is sigma_i times column i of N.
  m.r0 = VEC3(i2f_(ww + xx - yy - zz) * sx, i2f_(2 * (xy + wz)) * sx, i2f_(2 * (xz - wy)) * sx);
  m.r1 = VEC3(i2f_(2 * (xy - wz)) * sy, i2f_(ww - xx + yy - zz) * sy, i2f_(2 * (yz + wx)) * sy);
  m.r2 = VEC3(i2f_(2 * (xz + wy)) * sz, i2f_(2 * (yz - wx)) * sz, i2f_(ww - xx - yy + zz) * sz);
  m.t = VEC3(c.t[0], c.t[1], c.t[2]);
  return m;
}

KERNEL_NS_END
#endif
