// Occlusion queries on curves (the any-hit variant, MASQ_ANY_HIT): a shadow ray asks only
// whether the solid has a boundary point in its window [t_lo, tmax], not which one is
// nearest. Two certificates answer that without the closest-hit search's whole work:
//  - an interior point: a ray point at z_lo that lies inside some ball B(C(s), r) with
//    room for every rounding, while the point at z_max lies outside the curve's bounding
//    ball, so the ray must leave the solid in between. A shadow ray from the side of a
//    strand that faces away from the light goes back through that strand (about half of
//    them): the closest-hit search would locate its exit over several passes of the
//    subdivision (about 4,000 cycles a call on the bear's shadow rays), the witness
//    below takes a few curve evaluations.
//  - the first certified entry (curve_subdiv's zstop): once the subdivision has proved a
//    crossing at z <= z_max, with z_lo known to lie outside the solid or z_max outside
//    the bounding ball, the search stops there instead of looking for a nearer one.
//  - a ray point inside the solid anywhere in the window (curve_line_witness), where
//    the window's start lies outside the curve's bounding ball (so the ray enters the
//    solid before that point) or its end does (so it leaves after it). Most shadow rays
//    that meet a strand cross it: the curve point nearest the ray, found by a few Newton
//    steps on the part of the curve roving capsules' clipping leaves, proves it, where
//    the subdivision would locate the entry over several levels (measured on the bear's
//    curve shadow rays: docs/results.md, ninth round).
// Either way the closest-hit query on the same ray hits as well (its answer is the
// nearest crossing, at or before these), which tests/test_occlusion.cpp checks on every
// backend. The hit an occlusion query reports is the occluder and a point of the ray
// inside it or on its surface (t in the window), not necessarily its nearest crossing.
#ifndef MASQ_KERNEL_CURVE_OCCLUSION_H
#define MASQ_KERNEL_CURVE_OCCLUSION_H
#include "curve_frame.h"

// Newton steps towards the curve point nearest the ray point (any s is a witness: the
// steps only make one likely).
#define MASQ_WITNESS_STEPS 3

KERNEL_NS_BEGIN

// Whether X = (0, 0, z) (frame) lies inside the solid for certain: found = 1 when the
// ball at s holds X with a margin of 3 pad (pad, 64 u (M + r), bounds the frame's control
// points' error; the evaluation's rounding, at most a few u M, and that of X and of the
// distance fit in the rest). z is X's frame z; s and nrm (X - C(s), frame) describe it.
FN CurveRoot curve_inside_witness(CurveFrame f, float z, float pad) {
  CurveRoot w = curve_root_none(0.0f);
  vec3 x = VEC3(0.0f, 0.0f, z);
  vec3 ch = f.b3 - f.b0;
  float cc = dot(ch, ch);
  float s = cc > 0.0f ? min(max(dot(x - f.b0, ch) / cc, 0.0f), 1.0f) : 0.5f;
  CurvePoint e = curve_eval(f, s);
  vec3 v = e.p - x;
  for (int k = 0; k < MASQ_WITNESS_STEPS; ++k) {
    // Newton on (C(s) - X) . C'(s) = 0 where |C(s) - X|^2 is convex, else a fixed step
    // downhill (as curve_refine); steps of at most a quarter of the curve.
    float g = dot(v, e.d);
    float gd = dot(e.d, e.d) + dot(v, e.dd);
    float ds = gd > 0.0f ? min(max(g / gd, -0.25f), 0.25f) : (g > 0.0f ? 0.125f : -0.125f);
    s = min(max(s - ds, 0.0f), 1.0f);
    e = curve_eval(f, s);
    v = e.p - x;
  }
  float rin = f.r - 3.0f * pad;
  if (rin > 0.0f && dot(v, v) <= rin * rin) {
    w.found = 1;
    w.z = z;
    w.s = s;
    w.nrm = -v;
  }
  return w;
}

// Whether a ray point X = (0, 0, z) with zlo <= z <= zhi lies inside the solid for
// certain, looked for at the curve point nearest the ray (the ray is the frame's z axis):
// the ball at s holds X = (0, 0, C(s).z), the ray point nearest C(s), when
// rho^2(s) = x(s)^2 + y(s)^2 is below its radius squared. Newton steps on
// (rho^2)'/2 = x x' + y y' from the middle of [sa, sa + sw] (where it is convex, else a
// fixed step downhill), within that range; any s is a witness, the steps only make one
// likely. The margin, as curve_inside_witness's: 3 pad. found = 1 with z, s and the
// normal X - C(s) (frame). The caller must know the ray meets the solid's boundary in
// the window once X is inside (curve_intersect_mode: zlo outside the bounding ball, or
// zhi outside it).
FN CurveRoot curve_line_witness(CurveFrame f, float sa, float sw, float zlo, float zhi, float pad) {
  CurveRoot w = curve_root_none(0.0f);
  float lo = sa;
  float hi = sa + sw;
  float s = sa + 0.5f * sw;
  CurvePoint e = curve_eval(f, s);
  for (int k = 0; k < MASQ_WITNESS_STEPS; ++k) {
    float g = e.p.x * e.d.x + e.p.y * e.d.y;
    float gd = (e.d.x * e.d.x + e.d.y * e.d.y) + (e.p.x * e.dd.x + e.p.y * e.dd.y);
    float step = 0.125f * sw;
    float ds = gd > 0.0f ? min(max(g / gd, -0.25f), 0.25f) : (g > 0.0f ? step : -step);
    s = min(max(s - ds, lo), hi);
    e = curve_eval(f, s);
  }
  float rin = f.r - 3.0f * pad;
  float rho2 = e.p.x * e.p.x + e.p.y * e.p.y;
  if (rin > 0.0f && rho2 <= rin * rin && e.p.z >= zlo && e.p.z <= zhi) {
    w.found = 1;
    w.z = e.p.z;
    w.s = s;
    w.nrm = VEC3(-e.p.x, -e.p.y, 0.0f);
  }
  return w;
}

KERNEL_NS_END
#endif
