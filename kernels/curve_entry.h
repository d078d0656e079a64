// The ray's entry into the swept balls of one near-straight piece of a curve, found on
// the curve itself (roving capsules' coarse leaves, kernels/curve_roving.h).
//
// In the ray frame (the ray is the z axis) the ball at C(s) = (x, y, z) is entered at
// z_in(s) = z - sqrt(h), h = r^2 - x^2 - y^2, where h > 0. The piece's entry is the least
// z_in: at an end of the piece, or where z_in' = 0, i.e. where
//     D(s) = z' sqrt(max(h, 0)) + (x x' + y y') = 0
// (the envelope condition (X - C) . C' = 0 at X = (0, 0, z_in)). D has the sign of z_in'
// where the ray meets the ball, and the sign of x x' + y y' (the ray's distance from the
// curve shrinking or growing) where it does not, so it is continuous and changes sign
// from - to + at the least entry of a piece whose z_in is convex (a straight piece's is;
// a coarse leaf is flat to r / 8). A safeguarded Newton iteration on D inside the
// bracket finds it; t then has an error of second order in that of s.
#ifndef MASQ_KERNEL_CURVE_ENTRY_H
#define MASQ_KERNEL_CURVE_ENTRY_H
#include "curve_frame.h"

// Newton steps at most, and the bracket width (relative to the piece) that ends them.
#define MASQ_ENTRY_STEPS 12
#define MASQ_ENTRY_STOP 1.52587890625e-5f
// |D| below this times |C'| r ends them (see the loop).
#define MASQ_ENTRY_DTOL 2.44140625e-4f

KERNEL_NS_BEGIN

STRUCT_BEGIN(CurveEnvelope)
  float dv;    // D(s)
  float slope; // D'(s), where h > 0 (else 0)
  float h;
STRUCT_END(CurveEnvelope)

// zs = 1: for the entries z - sqrt(h); zs = -1: for the exits z + sqrt(h), as the
// entries of the curve mirrored in z (-z - sqrt(h) = -(z + sqrt(h))).
FN CurveEnvelope curve_envelope(CurvePoint e, float r, float zs) {
  CurveEnvelope v;
  float rho = sqrt(e.p.x * e.p.x + e.p.y * e.p.y);
  v.h = (r - rho) * (r + rho);
  float g = e.p.x * e.d.x + e.p.y * e.d.y;
  float sq = sqrt(max(v.h, 0.0f));
  v.dv = zs * e.d.z * sq + g;
  float gd = e.d.x * e.d.x + e.d.y * e.d.y + e.p.x * e.dd.x + e.p.y * e.dd.y;
  v.slope = v.h > 0.0f ? zs * (e.dd.z * sq - e.d.z * g / sq) + gd : 0.0f;
  return v;
}

// The least entry (zs = 1) or the greatest exit (zs = -1) of the piece [p0, p1] of the
// curve, starting from s (a guess inside); [sa, sb]: the part of the curve searched (no
// ball outside it meets the ray). found: 1 the entry or exit (z, s, outward normal,
// frame); 2 it is that of the ball at an end shared with a neighbouring piece, whose own
// reaches further (a bound, not a point of the surface); -1 not settled here (the
// caller splits the piece).
FN CurveRoot curve_piece_entry(CurveFrame f, float p0, float p1, float s, float sa, float sb, float zs) {
  CurveRoot rt = curve_root_none(s);
  rt.found = -1;
  CurveEnvelope v0 = curve_envelope(curve_eval(f, p0), f.r, zs);
  CurveEnvelope v1 = curve_envelope(curve_eval(f, p1), f.r, zs);
  int lo_up = v0.dv >= 0.0f ? 1 : 0;   // z_in rises from p0
  int hi_down = v1.dv <= 0.0f ? 1 : 0; // z_in falls towards p1
  if (lo_up != 0 && hi_down != 0) return rt; // not convex here
  // z_in rising from p0 (or falling to p1) all the way: the least entry is the ball's at
  // that end. If that ball misses the ray, the piece's z_in is not as assumed (the caller
  // knows the ray meets the piece): not settled. At an end the piece shares with a
  // neighbour (not an end of [sa, sb]; pieces' ends are at least a piece width apart, so
  // a quarter of one absorbs the rounding of their sums) it is not a point of the
  // surface, as the neighbour's balls reach further: found 2, a bound.
  float se = -1.0f;
  int at_joint = 0;
  if (lo_up != 0 || hi_down != 0) {
    float he = lo_up != 0 ? v0.h : v1.h;
    if (!(he > 0.0f)) return rt;
    se = lo_up != 0 ? p0 : p1;
    float q = 0.25f * (p1 - p0);
    at_joint = lo_up != 0 ? (p0 - sa > q ? 1 : 0) : (sb - p1 > q ? 1 : 0);
  }
  float lo = p0;
  float hi = p1;
  float tol = MASQ_ENTRY_STOP * (p1 - p0);
  if (se >= 0.0f) {
    s = se;
  } else {
    s = min(max(s, lo), hi);
    int done = 0;
    for (int k = 0; k < MASQ_ENTRY_STEPS && done == 0; ++k) {
      CurvePoint e = curve_eval(f, s);
      CurveEnvelope v = curve_envelope(e, f.r, zs);
      // Settled when D is below 2^-12 |C'| r: then t is off by about 2^-25 r (the
      // error of s is D / D', that of t is second order in it). Not by the size of a
      // step alone: where the ray grazes a ball, D' is huge and steps are tiny.
      if (fabs_(v.dv) <= MASQ_ENTRY_DTOL * f.r * length(e.d)) {
        done = 1;
      } else {
        if (v.dv < 0.0f) lo = s;
        else hi = s;
        float sn = v.slope > 0.0f ? s - v.dv / v.slope : 0.5f * (lo + hi);
        if (!(sn > lo && sn < hi)) sn = 0.5f * (lo + hi); // (NaN too)
        s = sn;
        if (hi - lo <= tol) done = 1; // bracketed to 2^-16 of the piece
      }
    }
    if (done == 0) return rt;
  }
  CurvePoint e = curve_eval(f, s);
  CurveEnvelope v = curve_envelope(e, f.r, zs);
  if (!(v.h > 0.0f)) return rt;
  if (se < 0.0f && !(v.slope > 0.0f)) return rt; // a maximum of z_in, not the entry
  float w = sqrt(v.h);
  rt.found = at_joint != 0 ? 2 : 1;
  rt.z = e.p.z - zs * w;
  rt.s = s;
  rt.nrm = VEC3(-e.p.x, -e.p.y, -zs * w);
  return rt;
}

KERNEL_NS_END
#endif
