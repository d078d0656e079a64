// Roving capsules: the second cubic-curve intersector (--curve-isect roving), after
// Reshetov & Hart, "Modeling Hair Strands with Roving Capsules" (SIGGRAPH 2024). The
// paper's idea as its abstract states it: intersect the ray with capsules defined at run
// time along the curve, after systematically eliminating the parts of the swept-ball
// solid that cannot meet the ray. masq's form of it, in the ray frame of curve_frame.h
// (the ray is the z axis):
//  0. Sieve. The curve is cut into MASQ_ROVING_PIECES equal pieces; a piece whose balls
//     lie in a capsule about its chord that misses the ray, or leaves it before the
//     search window starts, cannot meet the ray there; if no piece can, the call is a
//     miss. It runs where z_lo may lie in the curve's bounding ball (maybe_inside): a
//     secondary ray's calls on the curve it starts on and its neighbours, whose balls
//     it mostly leaves before z_lo, which clipping cannot show (the z cubic's hull is
//     too loose) and the subdivision showed only at its root's outer capsule. Elsewhere
//     clipping proves a miss about as cheaply, and the sieve would only add its cost to
//     the hits (measured: bear camera rays +2.8% instructions with it, +0.7% without).
//     The cpu tests the pieces in eight lanes
//     (curve_sieve_simd_cpp.h), with the same verdicts. The search below still starts
//     from the whole curve: starting it from the pieces kept changes which leaf answers,
//     and from there curve_refine's few Newton steps near a zero-speed end can settle on
//     the wrong foot point (tests/test_curve_intersector_shapes.cpp, degenerate points).
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
// Steps 0 and 1 discard only s where no ball can meet the ray: the pieces, rho and z
// are computed from control points whose error `pad` bounds (curve_subdiv.h); the
// sieve's capsules are widened by pad once more for the pieces' own rounding, and each
// clipping coefficient is moved by its own rounding bound before the test. Step 3 trusts the piece's z_in to
// have one minimum (true of a straight piece; the conditions above keep the pieces
// near that); everything else is the subdivision's certificate. Measured against the
// oracle like the phantom setting: tests/test_curve_intersector_*.cpp (every test runs
// both), `masq stress` (curve cells for each), docs/robustness.md.
#ifndef MASQ_KERNEL_CURVE_ROVING_H
#define MASQ_KERNEL_CURVE_ROVING_H
#include "curve_occlusion.h"
#include "curve_subdiv.h"
#include "curve_sieve_simd_cpp.h"

// Sieve pieces (step 0; a power of two: their weights are exact).
#define MASQ_ROVING_PIECES 8
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

// Step 0, the sieve: the curve cut at s = k / MASQ_ROVING_PIECES into pieces, each end
// a point and one piece's handle from curve_piece_end (de Casteljau: convex
// combinations, their rounding a few u of the largest frame coordinate, below pad).
// Whether the piece q0..q3 may hold a ball that meets the ray at or after zlo. It lies
// within dev (the larger distance of q1, q2 from the chord's thirds) of its chord, so
// its balls of radius rr (the radius with the sieve's own rounding allowance) lie in
// the capsule of radius rr + dev about the chord: the piece matters only if that
// capsule meets the z axis and leaves it at or after zlo. The exit is the later of the
// end balls' and, where the axis line's closest approach lies within the chord, the
// lateral surface's (as curve_chord_capsule). NaN keeps nothing.
FN int curve_sieve_keeps(vec3 q0, vec3 q1, vec3 q2, vec3 q3, float rr, float zlo) {
  float cx = q3.x - q0.x;
  float cy = q3.y - q0.y;
  float cz = q3.z - q0.z;
  float g1x = q1.x - (q0.x + cx * (1.0f / 3.0f));
  float g1y = q1.y - (q0.y + cy * (1.0f / 3.0f));
  float g1z = q1.z - (q0.z + cz * (1.0f / 3.0f));
  float g2x = q2.x - (q3.x - cx * (1.0f / 3.0f));
  float g2y = q2.y - (q3.y - cy * (1.0f / 3.0f));
  float g2z = q2.z - (q3.z - cz * (1.0f / 3.0f));
  float cap = rr + sqrt(max((g1x * g1x + g1y * g1y) + g1z * g1z, (g2x * g2x + g2y * g2y) + g2z * g2z));
  float cap2 = cap * cap;
  float zout = -inf_();
  float da = cap2 - (q0.x * q0.x + q0.y * q0.y);
  if (da >= 0.0f) zout = q0.z + sqrt(da);
  float db = cap2 - (q3.x * q3.x + q3.y * q3.y);
  if (db >= 0.0f) zout = max(zout, q3.z + sqrt(db));
  float aa = cx * cx + cy * cy;
  float ee = aa + cz * cz;
  float cr = q0.x * cy - q0.y * cx;
  float dl = cap2 - (cr * cr) / aa;
  if (aa > 1e-12f * ee && dl >= 0.0f) {
    float us = -(q0.x * cx + q0.y * cy) / aa; // the closest approach's chord parameter
    float hw = sqrt((dl * ee) / aa);
    float u = us + (hw * cz) / ee;
    if (u >= 0.0f && u <= 1.0f) zout = max(zout, (q0.z + us * cz) + hw);
  }
  return zout >= zlo ? 1 : 0;
}

// Bit k: the sieve keeps piece k (rr: the ball radius with the sieve's allowance).
FN uint curve_sieve_kept(CurveFrame f, float rr, float zlo) {
  float h = 1.0f / i2f_(MASQ_ROVING_PIECES);
  uint kept = 0u;
  uint bit = 1u; // 2^k
  CurvePieceEnd lo = curve_piece_end(f, 0.0f, h);
  for (int k = 0; k < MASQ_ROVING_PIECES; ++k) {
    CurvePieceEnd hi = curve_piece_end(f, i2f_(k + 1) * h, h);
    if (curve_sieve_keeps(lo.p, lo.p + lo.dh, hi.p - hi.dh, hi.p, rr, zlo) != 0) kept = kept | bit;
    lo = hi;
    bit = bit << 1u;
  }
  return kept;
}

// Whether the sieve keeps any piece (0: the ray misses the solid beyond zlo). The balls'
// radius is grown by pad twice: once for the frame's rounding, as everywhere in the
// search, once for the pieces' own.
FN int curve_roving_sieve(CurveFrame f, float pad, float zlo) {
  float rr = (f.r + pad) + pad;
#if defined(MASQ_LANG_CPP)
  // cpu: the eight pieces in eight lanes, the same verdicts (curve_sieve_simd_cpp.h).
  static_assert(MASQ_ROVING_PIECES == 8, "the cpu sieve tests eight pieces in eight lanes");
  const vec3 b[4] = {f.b0, f.b1, f.b2, f.b3};
  uint kept = simd::curve_sieve_mask8(b, rr, zlo);
#else
  uint kept = curve_sieve_kept(f, rr, zlo);
#endif
  return kept != 0u ? 1 : 0;
}

// The first boundary point of the solid at or after zlo, as curve_subdiv (same
// arguments), searching only the part of the curve that step 1 leaves. Step 0 is the
// caller's (curve_intersect_mode): where maybe_inside, it runs the sieve before anything
// else, the occlusion witness included, and calls this only when the sieve keeps a piece.
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
  // An occlusion query (zstop finite only where a point inside the solid in the window
  // proves a crossing there, curve_occlusion.h): the curve point nearest the ray on
  // what is left, before the search.
  if (zstop >= zlo) {
    CurveRoot wr = curve_line_witness(f, a, w, zlo, zstop, pad);
    if (wr.found != 0) return wr;
  }
  return curve_subdiv(f, a, w, zlo, zmax, tol, ttol, pad, maybe_inside, MASQ_ROVING_COARSE * f.r, zstop);
}

KERNEL_NS_END
#endif
