// Ray / cubic Bezier curve swept by a sphere of constant radius r (round ends, like
// Embree's round curves): the solid is the union of the balls B(C(s), r), s in [0,1],
// whatever the curve's shape (folds, cusps, radius of curvature below r, coincident
// control points). A hit is the nearest crossing of its boundary in [t_lo, tmax] (rays
// starting inside report their exit); t is in units of d (not normalised); normal:
// outward, unnormalised, in the ray's space; u = s.
//
// Both modes move to a ray-centric frame (origin near the curve, ray = +z axis).
//
// intersect_curve_fast -- Reshetov & Luebke, "Phantom Ray-Hair Intersector" (HPG 2018),
// as written in the paper (kernels/curve_phantom.h): iterate on s against the cylinder
// about the tangent line at C(s), one chain from each end on the near root (plus the
// far root when the origin may be inside), plus the end balls' outer hemispheres;
// plain subtraction for the origin shift; no self window. It assumes a hair-like curve
// (radius of curvature well above r) and may converge to a later crossing or none.
//
// intersect_curve (robust):
//  - the frame's origin is the ray point nearest the curve's centre, from an exact
//    o - centre (TwoSum) and a Dot2-accurate moment (o - centre) x d, so the curve's
//    offset from the ray does not carry an error of u |o - centre| (0.06 r at 10^6 radii);
//  - the first boundary point is found by certified subdivision of the curve
//    (kernels/curve_subdiv.h): pieces whose padded bounds cannot hold a better answer
//    are pruned, pieces flat to a fraction of the fp32 ambiguity band are capsules;
//  - the self window t_self (prim_hit.h; span: the control polygon's length).
// isect (the run's --curve-isect, MASQ_CURVE_ISECT): phantom is the above; roving
// (kernels/curve_roving.h) clips the curve to the part whose balls can meet the ray and
// settles most pieces at once by the envelope condition, in both modes (fast roving:
// the same search without the padding; the frame and self window as fast's).
// Measured against the long-double oracle in `masq stress` (docs/robustness.md) and
// tests/test_curve_intersector_*.cpp.
#ifndef MASQ_KERNEL_INTERSECT_CURVE_H
#define MASQ_KERNEL_INTERSECT_CURVE_H
#include "curve_occlusion.h"
#include "curve_phantom.h"
#include "curve_roving.h"

KERNEL_NS_BEGIN

// The first boundary point at or after zlo (frame z), by certified subdivision of the
// whole curve (phantom) or of what roving capsules' clipping leaves; zstop: an
// occlusion query's early stop (curve_subdiv). Roving: where inside, the caller has run
// roving's sieve and found a piece it keeps.
FN CurveRoot curve_search(CurveFrame f, int roving, float zlo, float tol, float pad, int inside, float zstop) {
  float ttol = MASQ_CURVE_TTOL * f.r;
  if (roving != 0) return curve_roving(f, zlo, inf_(), tol, ttol, pad, inside, zstop);
  return curve_subdiv(f, 0.0f, 1.0f, zlo, inf_(), tol, ttol, pad, inside, 0.0f, zstop);
}

// robust != 0: intersect_curve; 0: intersect_curve_fast (see the top of this file).
// isect: MASQ_CURVE_PHANTOM or MASQ_CURVE_ROVING (kernels/curve_roving.h).
// any != 0: an occlusion query's call (MASQ_ANY_HIT): any point of the window that
// proves the ray meets the solid will do (kernels/curve_occlusion.h).
FN PrimHit curve_intersect_mode(Curve c, vec3 o, vec3 d, float tmin, float tmax, int robust, int isect, int any) {
  float r = c.radius;
  float dd = dot(d, d);
  if (!(r > 0.0f) || !(dd > 0.0f) || !(tmin <= tmax)) return prim_miss();
  vec3 p0 = V3(c.p0);
  vec3 p1 = V3(c.p1);
  vec3 p2 = V3(c.p2);
  vec3 p3 = V3(c.p3);
  vec3 cen = 0.25f * ((p0 + p1) + (p2 + p3));
  vec3 q0 = p0 - cen;
  vec3 q1 = p1 - cen;
  vec3 q2 = p2 - cen;
  vec3 q3 = p3 - cen;
  // The solid lies in the ball of radius rb around cen (control-point hull plus r).
  float rb = sqrt(max(max(dot(q0, q0), dot(q1, q1)), max(dot(q2, q2), dot(q3, q3)))) + r;
  float rb2 = 1.001f * rb * rb;
  // Origin shift to the ray point nearest cen: pp (relative to cen), at t = ts.
  vec3 oc = o - cen;
  vec3 pp;
  float ts;
  if (robust != 0) {
    // o - cen = oc + ol exactly (TwoSum); moment (o - cen) x d to ~1 ulp; then
    // pp = d x ((o - cen) x d) / dd has an error of the size of u |pp|, not u |o - cen|.
    vec3 bv = oc - o;
    vec3 av = oc - bv;
    vec3 ol = (o - av) - (cen + bv);
    vec3 mom = curve_cross_acc(oc, d) + cross(ol, d);
    pp = cross(d, mom) / dd;
    ts = -(curve_dot_acc(oc, d) + dot(ol, d)) / dd; // t of the shifted origin, to ~1 ulp
  } else {
    ts = -dot(oc, d) / dd;
    pp = oc + ts * d;
  }
  if (!(dot(pp, pp) <= rb2)) return prim_miss(); // misses the bounding ball (or NaN)
  // Self window (prim_hit.h); span: the control polygon's length.
  float span = length(p1 - p0) + length(p2 - p1) + length(p3 - p2);
  float tlo = robust != 0 ? max(tmin, self_eps_t_span(r, oc, span, dd)) : tmin;
  // Ray-centric frame: z along d (Duff et al.'s orthonormal basis), origin at pp.
  float dl = sqrt(dd);
  vec3 ez = d / dl;
  float sg = ez.z >= 0.0f ? 1.0f : -1.0f;
  float ia = -1.0f / (sg + ez.z);
  float bxy = ez.x * ez.y * ia;
  vec3 ex = VEC3(1.0f + sg * ez.x * ez.x * ia, sg * bxy, -sg * ez.x);
  vec3 ey = VEC3(bxy, sg + ez.y * ez.y * ia, -ez.y);
  CurveFrame f;
  f.b0 = curve_to_frame(q0 - pp, ex, ey, ez);
  f.b1 = curve_to_frame(q1 - pp, ex, ey, ez);
  f.b2 = curve_to_frame(q2 - pp, ex, ey, ez);
  f.b3 = curve_to_frame(q3 - pp, ex, ey, ez);
  f.r = r;
  vec3 e0 = f.b1 - f.b0;
  vec3 e1 = f.b2 - f.b1;
  vec3 e2 = f.b3 - f.b2;
  float l0 = dot(e0, e0);
  float l1 = dot(e1, e1);
  float l2 = dot(e2, e2);
  float sc = max(l0, max(l1, l2));
  float tiny = 1e-12f * sc;
  f.t0 = 3.0f * (l0 > tiny ? e0 : (l1 > tiny ? e1 : e2));
  f.t1 = 3.0f * (l2 > tiny ? e2 : (l1 > tiny ? e1 : e0));
  f.deg2 = 9.0f * tiny;

  PrimHit best = prim_miss();
  best.t = tmax;
  float zlo = (tlo - ts) * dl;
  int roving = isect == MASQ_CURVE_ROVING ? 1 : 0;
  if (robust != 0 || roving != 0) {
    // Certified subdivision (curve_subdiv.h), of the whole curve or of what roving
    // capsules' clipping leaves (curve_roving.h); fast roving drops the padding. pad: the rounding of the extracted
    // control points, a few u of the largest frame coordinate; tol: the leaf flatness.
    vec3 mb = max(max(vabs_(f.b0), vabs_(f.b1)), max(vabs_(f.b2), vabs_(f.b3)));
    float pad = robust != 0 ? 64.0f * MASQ_U * (vmax3_(mb.x, mb.y, mb.z) + r) : 0.0f;
    // tol: the leaf flatness; never below 4 u M, the rounding noise of dev itself (a
    // zero-speed end's pieces would otherwise never count as flat).
    float tol = max(MASQ_CURVE_FLAT * MASQ_U * (r + span), 4.0f * MASQ_U * vmax3_(mb.x, mb.y, mb.z));
    int inside = dot(pp, pp) + zlo * zlo <= rb2 ? 1 : 0; // zlo may lie in the solid
    // Occlusion (curve_occlusion.h): the window's far end outside the bounding ball lets
    // a point inside the solid prove a crossing; with zlo outside, any entry found does.
    float zmax = (tmax - ts) * dl;
    int far_out = zmax > zlo && dot(pp, pp) + zmax * zmax > rb2 ? 1 : 0;
    // Roving's sieve (curve_roving.h, step 0) where zlo may lie in the solid: it shows
    // most of these calls (the curve a secondary ray starts on, and its neighbours) to
    // miss beyond zlo, and then the interior witness cannot succeed either (it proves a
    // point of the window inside the solid), so it runs first: on the bear's curve
    // shadow rays 47% of the witness's calls ended in the sieve's miss.
    int sieved_out = 0;
    if (roving != 0 && inside != 0) sieved_out = curve_roving_sieve(f, pad, zlo) == 0 ? 1 : 0;
    CurveRoot rt = curve_root_none(0.0f);
    if (sieved_out == 0 && any != 0 && inside != 0 && far_out != 0) rt = curve_inside_witness(f, zlo, pad);
    int witness = rt.found; // (a witness lies at zlo, i.e. at tlo itself: taken as such)
    float zstop = any != 0 && (inside == 0 || far_out != 0) ? zmax : -inf_();
    // The search ignores tmax: it settles near-ties within ttol by its own visit order,
    // so a bound from another primitive (the traversal's nearest hit so far) would
    // prune this curve's entry when it lies within ttol before that hit, and the answer
    // would depend on the order a backend visits primitives in (ray query's driver
    // order differs from masq's). tmax decides only the answer's acceptance below (and
    // an occlusion query's early stop, zstop).
    if (rt.found == 0 && sieved_out == 0) rt = curve_search(f, roving, zlo, tol, pad, inside, zstop);
    if (rt.found != 0) best = prim_take(best, witness != 0 ? tlo : ts + rt.z / dl, tlo, rt.nrm, rt.s);
    // An early stop's entry that its refinement moved before zlo (onto the surface a
    // shadow ray starts on, going back through the strand) is no crossing in the window:
    // then the whole search decides (tests/test_curve_occlusion.cpp found 0.2% of such
    // rays missed with the phantom setting).
    if (rt.found != 0 && best.hit == 0 && witness == 0 && zstop >= zlo) {
      rt = curve_search(f, roving, zlo, tol, pad, inside, -inf_());
      if (rt.found != 0) best = prim_take(best, ts + rt.z / dl, tlo, rt.nrm, rt.s);
    }
  }
  // Fast: exit chains only when the origin (at tlo) may be inside the solid.
  int maybe_inside = dot(pp, pp) + zlo * zlo <= rb2 ? 1 : 0;
  if (sc > 0.0f && robust == 0 && roving == 0) {
    for (int k = 0; k < 4; ++k) {
      if (k >= 2 && maybe_inside == 0) break;
      float s0 = (k & 1) == 0 ? 0.0f : 1.0f;
      float side = k < 2 ? -1.0f : 1.0f;
      CurveRoot rt = curve_chain_fast(f, s0, side);
      if (rt.found != 0) best = prim_take(best, ts + rt.z / dl, tlo, rt.nrm, rt.s);
    }
  }
  // Fast: end balls, outer hemispheres (overlapping the tube at the seam).
  for (int e = 0; e < 2 && robust == 0 && roving == 0; ++e) {
    vec3 bc = e == 0 ? f.b0 : f.b3;
    vec3 ta = e == 0 ? -f.t0 : f.t1; // outward axis at that end
    float hc = sqrt(bc.x * bc.x + bc.y * bc.y);
    float disc = (r - hc) * (r + hc);
    if (disc >= 0.0f) {
      float q = sqrt(disc);
      float seam = -MASQ_CURVE_SEAM * r * sqrt(dot(ta, ta));
      for (int k = 0; k < 2; ++k) {
        float z = k == 0 ? bc.z - q : bc.z + q;
        vec3 w = VEC3(-bc.x, -bc.y, z - bc.z);
        if (dot(w, ta) >= seam) best = prim_take(best, ts + z / dl, tlo, w, e == 0 ? 0.0f : 1.0f);
      }
    }
  }
  if (best.hit == 0) return prim_miss();
  vec3 nf = best.normal;
  best.normal = nf.x * ex + nf.y * ey + nf.z * ez;
  return best;
}

FN PrimHit intersect_curve(Curve c, vec3 o, vec3 d, float tmin, float tmax) {
  return curve_intersect_mode(c, o, d, tmin, tmax, 1, MASQ_CURVE_PHANTOM, 0);
}

FN PrimHit intersect_curve_fast(Curve c, vec3 o, vec3 d, float tmin, float tmax) {
  return curve_intersect_mode(c, o, d, tmin, tmax, 0, MASQ_CURVE_PHANTOM, 0);
}

FN PrimHit intersect_curve_roving(Curve c, vec3 o, vec3 d, float tmin, float tmax) {
  return curve_intersect_mode(c, o, d, tmin, tmax, 1, MASQ_CURVE_ROVING, 0);
}

FN PrimHit intersect_curve_roving_fast(Curve c, vec3 o, vec3 d, float tmin, float tmax) {
  return curve_intersect_mode(c, o, d, tmin, tmax, 0, MASQ_CURVE_ROVING, 0);
}

KERNEL_NS_END
#endif
