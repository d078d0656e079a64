// Roving capsules: the second cubic-curve intersector (--curve-isect roving), after
// Reshetov & Hart, "Modeling Hair Strands with Roving Capsules" (SIGGRAPH 2024). The
// paper's idea as its abstract states it: intersect the ray with capsules defined at run
// time along the curve, after systematically eliminating the parts of the swept-ball
// solid that cannot meet the ray. masq's form of it, in the ray frame of curve_frame.h
// (the ray is the z axis):
//  1. Elimination. A ball B(C(s), r) meets the ray only where the curve's distance from
//     the z axis is at most r: rho^2(s) = x(s)^2 + y(s)^2 <= r^2. rho^2 of a cubic is a
//     degree-6 polynomial whose Bernstein coefficients are sums of the control points'
//     xy dot products, and the graph lies in the convex hull of its control points
//     (k/6, c_k), so only the s where that hull reaches below r^2 can hold a hit. The
//     same for the balls that end before the search window starts (z(s) + r < z_lo:
//     a cubic). The surviving range is clipped again, as in Bezier clipping, while it
//     shrinks by at least half (MASQ_ROVING_CLIPS at most).
//  2. Capsules. On what is left -- for a ray across a hair, a piece about 2r long --
//     the certified subdivision of curve_subdiv.h runs with that piece as its root:
//     each node's chord capsules of radius r -+ (dev + pad) prune it or prove a hit.
//  3. Coarse leaves. A node flat to r / 8 (MASQ_ROVING_COARSE) whose inner capsule the
//     ray crosses, starting before its outer one, at an angle to its chord, and which
//     runs one way along that chord, is a leaf at once: its least entry is found on the
//     curve by the envelope condition (kernels/curve_entry.h) and must lie in the band
//     the two capsules leave, or the node is split as before. The phantom setting
//     descends until a node is flat to ttol (7.8e-3 r) or to the fp32 grain, then
//     projects the capsule's hit onto the curve (curve_refine).
// Step 1 discards only s where no ball can meet the ray: rho and z are computed from
// control points whose error `pad` bounds (curve_subdiv.h), and each coefficient is
// moved by its own rounding bound before the test. Step 3 trusts the piece's z_in to
// have one minimum (true of a straight piece; the conditions above keep the pieces
// near that); everything else is the subdivision's certificate. Measured against the
// oracle like the phantom setting: tests/test_curve_intersector_*.cpp (every test runs
// both), `masq stress` (curve cells for each), docs/robustness.md.
#ifndef MASQ_KERNEL_CURVE_ROVING_H
#define MASQ_KERNEL_CURVE_ROVING_H
#include "curve_subdiv.h"

// Clipping rounds at most (each must halve the range to go on).
#define MASQ_ROVING_CLIPS 4
// Coarse leaves: pieces flat to this times r (step 3).
#define MASQ_ROVING_COARSE 0.125f

KERNEL_NS_BEGIN

// [lo, hi]: where a Bernstein polynomial of degree n (coefficients c[0..n], n <= 6) may be
// <= 0 on [0, 1]: the crossing of the axis by the hull of its control points (k/n, c_k).
// lo > hi: nowhere. A NaN coefficient gives [0, 1] (the subdivision then prunes).
STRUCT_BEGIN(CurveClip)
  float lo;
  float hi;
STRUCT_END(CurveClip)

FN CurveClip curve_clip_hull(float c[7], int n) {
  CurveClip cl;
  cl.lo = 2.0f;
  cl.hi = -1.0f;
  float inv = 1.0f / i2f_(n);
  // (No return inside a loop: a compiler merges such returns through a value that is
  // undefined on the other paths.)
  int nan = 0;
  for (int i = 0; i <= n; ++i)
    if (!(c[i] == c[i])) nan = 1;
  if (nan != 0) {
    cl.lo = 0.0f;
    cl.hi = 1.0f;
    return cl;
  }
  for (int i = 0; i <= n; ++i) {
    if (c[i] <= 0.0f) {
      cl.lo = min(cl.lo, i2f_(i) * inv);
      cl.hi = max(cl.hi, i2f_(i) * inv);
    } else {
      // Every edge from this positive point to a non-positive one crosses the axis.
      for (int j = 0; j <= n; ++j) {
        if (c[j] <= 0.0f) {
          float s = (i2f_(i) + i2f_(j - i) * (c[i] / (c[i] - c[j]))) * inv;
          cl.lo = min(cl.lo, s);
          cl.hi = max(cl.hi, s);
        }
      }
    }
  }
  return cl;
}

// Step 1 on the piece pc of the curve: the part of it (in its own parameter) where a ball
// of radius rp = r + pad may meet the ray at or after zlo.
FN CurveClip curve_roving_clip(CurvePiece pc, float rp, float zlo) {
  float c[7];
  // rho^2 in Bernstein form: the product of two cubics' Bernstein bases,
  // B3_i B3_j = C(3,i) C(3,j) / C(6,i+j) B6_(i+j).
  float d00 = pc.p0.x * pc.p0.x + pc.p0.y * pc.p0.y;
  float d01 = pc.p0.x * pc.p1.x + pc.p0.y * pc.p1.y;
  float d02 = pc.p0.x * pc.p2.x + pc.p0.y * pc.p2.y;
  float d03 = pc.p0.x * pc.p3.x + pc.p0.y * pc.p3.y;
  float d11 = pc.p1.x * pc.p1.x + pc.p1.y * pc.p1.y;
  float d12 = pc.p1.x * pc.p2.x + pc.p1.y * pc.p2.y;
  float d13 = pc.p1.x * pc.p3.x + pc.p1.y * pc.p3.y;
  float d22 = pc.p2.x * pc.p2.x + pc.p2.y * pc.p2.y;
  float d23 = pc.p2.x * pc.p3.x + pc.p2.y * pc.p3.y;
  float d33 = pc.p3.x * pc.p3.x + pc.p3.y * pc.p3.y;
  // Each coefficient is a convex combination of dot products no larger than m2, so its
  // rounding is below 8 u (m2 + rp^2); subtracting that keeps the test conservative.
  float m2 = max(max(d00, d11), max(d22, d33));
  float rr = rp * rp;
  float sub = rr + 8.0f * MASQ_U * (m2 + rr);
  c[0] = d00 - sub;
  c[1] = d01 - sub;
  c[2] = (0.4f * d02 + 0.6f * d11) - sub;
  c[3] = (0.1f * d03 + 0.9f * d12) - sub;
  c[4] = (0.4f * d13 + 0.6f * d22) - sub;
  c[5] = d23 - sub;
  c[6] = d33 - sub;
  CurveClip cl = curve_clip_hull(c, 6);
  // The balls that end before zlo: z(s) + rp < zlo, i.e. zlo - rp - z(s) > 0 (a cubic).
  float mz = vmax3_(fabs_(pc.p0.z), fabs_(pc.p1.z), max(fabs_(pc.p2.z), fabs_(pc.p3.z)));
  float zs = (zlo - rp) - 4.0f * MASQ_U * (fabs_(zlo) + rp + mz);
  c[0] = zs - pc.p0.z;
  c[1] = zs - pc.p1.z;
  c[2] = zs - pc.p2.z;
  c[3] = zs - pc.p3.z;
  CurveClip cz = curve_clip_hull(c, 3);
  cl.lo = max(cl.lo, cz.lo);
  cl.hi = min(cl.hi, cz.hi);
  return cl;
}

// The first boundary point of the solid at or after zlo, as curve_subdiv (same
// arguments), searching only the part of the curve that steps 1 and 2 leave.
// zstop: as curve_subdiv's (an occlusion query's early stop).
FN CurveRoot curve_roving(CurveFrame f, float zlo, float zmax, float tol, float ttol, float pad, int maybe_inside,
                          float zstop) {
  float a = 0.0f; // the piece left: s in [a, a + w]
  float w = 1.0f;
  CurvePiece pc;
  pc.p0 = f.b0;
  pc.p1 = f.b1;
  pc.p2 = f.b2;
  pc.p3 = f.b3;
  int missed = 0; // (a flag, not a return inside the loop: see curve_clip_hull)
  for (int it = 0; it < MASQ_ROVING_CLIPS; ++it) {
    CurveClip cl = curve_roving_clip(pc, f.r + pad, zlo);
    if (!(cl.lo <= cl.hi)) {
      missed = 1;
      break;
    }
    // Widened by the rounding of the crossings (relative) and of a + w lo (absolute: s
    // is in [0, 1], whose ulp is at most 2^-23).
    float lo = max(cl.lo - 9.5367431640625e-7f, 0.0f);
    float hi = min(cl.hi + 9.5367431640625e-7f, 1.0f);
    float na = max(a + w * lo - 1.1920928955078125e-7f, 0.0f);
    float nb = min(a + w * hi + 1.1920928955078125e-7f, 1.0f);
    int more = hi - lo <= 0.5f ? 1 : 0;
    a = na;
    w = nb - na;
    if (more == 0 || it + 1 == MASQ_ROVING_CLIPS) break;
    pc = curve_piece(f, a, nb);
  }
  if (missed != 0) return curve_root_none(0.0f);
  return curve_subdiv(f, a, w, zlo, zmax, tol, ttol, pad, maybe_inside, MASQ_ROVING_COARSE * f.r, zstop);
}

KERNEL_NS_END
#endif
