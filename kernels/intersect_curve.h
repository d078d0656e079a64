// Ray / cubic Bezier curve swept by a sphere of constant radius r (round ends, like
// Embree's round curves): the solid is the union of the balls B(C(s), r), s in [0,1].
// Its boundary is the tube envelope -- the circles of radius r about C(s) perpendicular
// to C'(s) -- plus the outer halves of the end balls at p0 and p3 (for hair-like curves:
// radius of curvature above r, no fold-back within 2r). A hit is the nearest crossing of
// that boundary in [t_lo, tmax] (rays starting inside report their exit); t is in units
// of d (not normalised); normal: outward, unnormalised, in the ray's space; u = s.
//
// Both modes follow Reshetov & Luebke, "Phantom Ray-Hair Intersector" (HPG 2018): move
// to a ray-centric frame (origin near the curve, ray = z axis), then iterate on the
// curve parameter s. At each s a local primitive about C(s) is intersected with the
// ray, and the offset of that hit X from the plane through C(s) perpendicular to C'(s),
//   R(s) = (X - C(s)) . C'(s),
// over the derivative, updates s. A root puts X on the circle of s: on the envelope.
// The end balls are closed-form spheres, kept on their outer hemisphere only (the inner
// one lies inside the tube: no crossing of the union).
//
// intersect_curve_fast -- the paper's loop as written: the local primitive is the
// cylinder about the tangent line (its "cone" with zero slope), the update R / |C'|^2
// (slope of a straight curve), steps clamped to 0.5, regula falsi when the update
// changes sign (bisection every 4th iteration), |ds| < 5e-5 in curve-parameter units,
// one chain from each end (s = 0 and s = 1) on the cylinder's near root, plus the same
// on the far root when the origin may be inside; plain subtraction for the origin
// shift; no self window. At most MASQ_CURVE_ITERS steps per chain.
//
// intersect_curve (robust):
//  - the frame's origin is the ray point nearest the curve's centre, from an exact
//    o - centre (TwoSum) and a Dot2-accurate moment (o - centre) x d, so the curve's
//    offset from the ray does not carry an error of u |o - centre| (0.06 r at 10^6 radii);
//  - the residual is taken on the ball at C(s) (the swept sphere itself), where it
//    brackets (see "robust mode" below): phase 1 walks to the ray's closest approach
//    to the curve by Newton's method with C'' (the phantom steps), phase 2 to the
//    crossing with the paper's cylinder step as predictor, kept inside the bracket;
//  - chains start at the two most promising minima of the curve's distance from the ray
//    line (sampled) and at both ends; entry and exit crossings;
//  - tolerances scaled to r: the closest approach to 2^-10 r along the curve, crossings
//    to 2^-7 r from the normal plane (the error in t is second order in that: ~3e-5 r);
//  - discriminants as (r - h)(r + h); the self window t_self (prim_hit.h; span: the
//    control polygon's length).
// At most MASQ_CURVE_ITERS steps per phase and start; most rays stop after 2 to 5, so
// the limit costs time only on hard rays. Measured against the long-double oracle
// (tests/test_curve_intersector_*.cpp): at 12 no disagreement outside the fp32 band on
// 57,600 random and silhouette rays (at 8: 8 of them, 1.4e-4); rays within ~0.03 rad
// of a bent curve's tangent remain the weak spot (1.2e-3 flips, 0.7e-3 wrong
// crossings at 12; the paper's loop: 3.9% and 2.2%).
// Recommended: MASQ_CURVE_ITERS = 12.
#ifndef MASQ_KERNEL_INTERSECT_CURVE_H
#define MASQ_KERNEL_INTERSECT_CURVE_H
#include "prim_hit.h"
#include "variants.h" // MASQ_CURVE_ITERS

// The error-free products below are two_prod_err_ (shim.h): exact on every backend, so
// the accurate dot products give the same bits everywhere (no backend contracts or
// reorders the transforms around them: shim.h, "Contraction").

// Robust: closest approach converged when its step is below this times r along the
// curve (the distance it decides hit/miss by is then off by ~5e-7 r); also the
// overlap of the end balls and the tube at the seam.
#define MASQ_CURVE_TOL 9.765625e-4f
// Robust: a crossing is accepted within this times r of the normal plane; the entry
// of the ball family is stationary there, so t is off by ~tol^2 r / 2.
#define MASQ_CURVE_TOL_CROSS 7.8125e-3f
// Robust: samples of the curve's distance from the ray line that choose the starts.
#ifndef MASQ_CURVE_SEEDS
#define MASQ_CURVE_SEEDS 16
#endif
// Fast: the paper's |ds| bound in curve-parameter units.
#define MASQ_CURVE_FAST_TOL 5e-5f

KERNEL_NS_BEGIN

// The curve in the ray-centric frame: the ray is the +z axis through the origin, z in
// units of length (t = ts + z / |d|).
STRUCT_BEGIN(CurveFrame)
  vec3 b0;
  vec3 b1;
  vec3 b2;
  vec3 b3;
  vec3 t0;    // tangent used at s = 0 (3 * first non-zero control difference)
  vec3 t1;    // tangent used at s = 1
  float r;
  float deg2; // |C'|^2 below this counts as a degenerate (zero) tangent
STRUCT_END(CurveFrame)

STRUCT_BEGIN(CurvePoint)
  vec3 p;
  vec3 d;
  vec3 dd; // second derivative
STRUCT_END(CurvePoint)

// A crossing found by a chain: frame z of the hit, curve parameter, outward normal
// (frame coordinates).
STRUCT_BEGIN(CurveRoot)
  int found;
  float z;
  float s;
  vec3 nrm;
STRUCT_END(CurveRoot)

// de Casteljau: point and derivative; a zero derivative (p0 == p1, ...) is replaced by
// the limit direction at the nearer end, so no step divides by zero.
FN CurvePoint curve_eval(CurveFrame f, float s) {
  float s1 = 1.0f - s;
  vec3 a = s1 * f.b0 + s * f.b1;
  vec3 b = s1 * f.b1 + s * f.b2;
  vec3 c = s1 * f.b2 + s * f.b3;
  vec3 ab = s1 * a + s * b;
  vec3 bc = s1 * b + s * c;
  CurvePoint e;
  e.p = s1 * ab + s * bc;
  e.d = 3.0f * (bc - ab);
  e.dd = 6.0f * ((c - b) - (b - a));
  if (!(dot(e.d, e.d) > f.deg2)) e.d = s < 0.5f ? f.t0 : f.t1;
  return e;
}

// ---------------------------------------------------------------- fast mode

// One phantom step at s (the paper's): the ray against the cylinder of radius r about
// the tangent line at C(s). side -1: its near root (entry), +1: its far root (exit).
STRUCT_BEGIN(CurveStep)
  int ok;      // tangent usable (not zero, not parallel to the ray)
  int real;    // the ray meets the cylinder
  float z;     // the ray's crossing of the cylinder (closest approach if none)
  float g;     // update of s
  vec3 nrm;    // outward normal at the crossing (frame coordinates)
STRUCT_END(CurveStep)

FN CurveStep curve_step(CurveFrame f, float s, float side) {
  CurvePoint e = curve_eval(f, s);
  vec3 c0 = e.p;
  vec3 cd = e.d;
  CurveStep st;
  st.ok = 0;
  st.real = 0;
  st.z = 0.0f;
  st.g = 0.0f;
  st.nrm = VEC3(0.0f, 0.0f, 0.0f);
  float dd2 = dot(cd, cd);
  float aa = cd.x * cd.x + cd.y * cd.y; // |C'|^2 sin^2(angle between axis and ray)
  if (!(aa > 1e-14f * dd2)) return st;  // zero tangent, axis parallel to the ray, NaN
  float cdd = c0.x * cd.x + c0.y * cd.y;
  float cxd = c0.x * cd.y - c0.y * cd.x;
  float inv = 1.0f / aa;
  float h = fabs_(cxd) * sqrt(inv); // distance between the ray and the axis line
  float disc = (f.r - h) * (f.r + h);
  float hw = sqrt(max(disc, 0.0f) * dd2 * inv);
  float zeta = -cd.z * cdd * inv + side * hw; // crossing (or closest approach) - c0.z
  float ax = zeta * cd.z - cdd;                   // (X - C(s)) . C'(s)
  st.ok = 1;
  st.real = disc >= 0.0f ? 1 : 0;
  st.z = c0.z + zeta;
  st.g = ax / dd2;
  st.nrm = VEC3(-c0.x, -c0.y, zeta) - st.g * cd;
  return st;
}

// The paper's chain: steps clamped to 0.5; on a sign change regula falsi between the
// last two iterates, bisection every 4th iteration; stops when s leaves [0,1]. (Stops
// also when it converges on a miss, which the paper lets run to the limit: same result.)
FN CurveRoot curve_chain_fast(CurveFrame f, float s0, float side) {
  CurveRoot rt;
  rt.found = 0;
  rt.z = 0.0f;
  rt.s = s0;
  rt.nrm = VEC3(0.0f, 0.0f, 0.0f);
  float s = s0;
  float sold = s0;
  float g1 = 0.0f;
  float g2 = 0.0f;
  for (int k = 0; k < MASQ_CURVE_ITERS; ++k) {
    CurveStep st = curve_step(f, s, side);
    if (st.ok == 0) break;
    if (fabs_(st.g) < MASQ_CURVE_FAST_TOL) {
      if (st.real != 0) {
        rt.found = 1;
        rt.z = st.z;
        rt.s = s;
        rt.nrm = st.nrm;
      }
      break;
    }
    g1 = g2;
    g2 = min(max(st.g, -0.5f), 0.5f);
    float sn = s + g2;
    if (g1 * g2 < 0.0f) sn = (k & 3) == 0 ? 0.5f * (sold + s) : (g2 * sold - g1 * s) / (g2 - g1);
    sold = s;
    s = sn;
    if (s < 0.0f || s > 1.0f) break;
  }
  return rt;
}

// ---------------------------------------------------------------- robust mode

// The solid is the union of the balls B(C(s), r). In the ray frame the ray meets the
// ball at s iff q(s) = |C_xy(s)|^2 <= r^2, at z = C_z -+ w, w = sqrt(r^2 - q); the
// solid's entry is the least of the entries, its exit the greatest of the exits. With
// q1 = C_xy . C'_xy (= q'/2), the paper's residual -- the offset of the hit X from the
// plane through C(s) perpendicular to C'(s) -- is, for this primitive,
//   R(s) = (X - C(s)) . C'(s) = -q1 + side w C'_z        (side -1 entry, +1 exit)
// and its roots are the phantom fixed points (X on the circle of s: on the envelope).
// The paper intersects the cylinder about the tangent line instead: exact for a
// straight tube, but for a ray running nearly along a bent curve its crossing lies
// r / sin(angle) away and moves by as much per unit of tilt, so its steps go astray
// (measured with the cylinder throughout: 3% of near-parallel rays wrong at 8
// iterations, 1% at 16, with the same starts). The ball's
// residual brackets instead: on an s-interval where the ray is within r, R's roots are
// those of P = q1^2 - w^2 C'_z^2 (a polynomial: no square root), P < 0 between the two
// fixed points (e.g. at the closest approach, q1 = 0) and P = q1^2 >= 0 at the ends of
// the interval, where the ray just touches the ball.

STRUCT_BEGIN(CurveBall)
  vec3 c0;  // C(s), C'(s), C''(s) in the ray frame
  vec3 cd;
  vec3 c2;
  float w2; // r^2 - q: the ray meets the ball iff w2 >= 0
  float q1; // C_xy . C'_xy
  float q2; // |C'_xy|^2 + C_xy . C''_xy (= q''/2)
  float pp; // P = q1^2 - w2 C'_z^2
  float dp; // P'
STRUCT_END(CurveBall)

FN CurveBall curve_ball(CurveFrame f, float s) {
  CurvePoint e = curve_eval(f, s);
  CurveBall b;
  b.c0 = e.p;
  b.cd = e.d;
  b.c2 = e.dd;
  float rho = sqrt(e.p.x * e.p.x + e.p.y * e.p.y);
  b.w2 = (f.r - rho) * (f.r + rho);
  b.q1 = e.p.x * e.d.x + e.p.y * e.d.y;
  b.q2 = e.d.x * e.d.x + e.d.y * e.d.y + e.p.x * e.dd.x + e.p.y * e.dd.y;
  b.pp = b.q1 * b.q1 - b.w2 * e.d.z * e.d.z;
  b.dp = 2.0f * (b.q1 * (b.q2 + e.d.z * e.d.z) - b.w2 * e.d.z * e.dd.z);
  return b;
}

// Phase 1, the phantom steps: Newton on q' = 0 (the closest approach of C(s) to the
// ray, with C'' in the slope) from s0 until the ray is within r of C(s) between the two
// fixed points (w2 >= 0, P <= 0). found = 0: the closest approach misses the ball (to
// within tol along the curve) or lies beyond an end (the end ball covers that).
FN CurveRoot curve_approach(CurveFrame f, float s0, float tol, float maxstep) {
  CurveRoot rt;
  rt.found = 0;
  rt.z = 0.0f;
  rt.s = s0;
  rt.nrm = VEC3(0.0f, 0.0f, 0.0f);
  float s = s0;
  for (int k = 0; k < MASQ_CURVE_ITERS; ++k) {
    CurveBall b = curve_ball(f, s);
    float ds = b.q2 > 0.0f ? -b.q1 / b.q2 : (b.q1 > 0.0f ? -0.125f : 0.125f);
    int conv = b.q2 > 0.0f && fabs_(ds) * length(b.cd) <= tol ? 1 : 0;
    if (b.w2 >= 0.0f && (b.pp <= 0.0f || conv != 0)) {
      rt.found = 1;
      rt.s = s;
      break;
    }
    if (conv != 0) break; // the closest approach misses
    float sn = min(max(s + min(max(ds, -maxstep), maxstep), 0.0f), 1.0f);
    if (!(sn != s)) break; // stuck at an end (or NaN)
    s = sn;
  }
  return rt;
}

// Phase 2: from sa (w2 >= 0, P <= 0) towards the fixed point of this side, which lies
// between sa and where the ray leaves the ball interval (P >= 0 there). Steps are
// predicted by the paper's cylinder step (exact for a straight tube). Until a point
// with P >= 0 brackets the fixed point, a prediction that does not point outwards is
// replaced by steps that double, starting where the quadratic model of q reaches r^2;
// inside the bracket: the prediction, else Newton on P, else Illinois regula falsi,
// and bisection every 4th step. Accepts a crossing within tol of the normal plane
// (|R| / |C'| <= tol); found = 0 if the fixed point lies beyond an end (end ball).
FN CurveRoot curve_crossing(CurveFrame f, float sa, float side, float tol) {
  CurveRoot rt;
  rt.found = 0;
  rt.z = 0.0f;
  rt.s = sa;
  rt.nrm = VEC3(0.0f, 0.0f, 0.0f);
  float a = sa; // P <= 0
  float pa = 0.0f;
  float b = sa; // P >= 0 once have_b
  float pb = 0.0f;
  int have_b = 0;
  int last = 0;
  float dir = 0.0f;
  float reach = 0.0f; // outward search step before a bracket exists (doubles)
  float s = sa;
  for (int k = 0; k < MASQ_CURVE_ITERS; ++k) {
    CurveBall c = curve_ball(f, s);
    float cn = length(c.cd);
    if (c.w2 >= 0.0f) {
      float w = sqrt(c.w2);
      float rr = side * w * c.cd.z - c.q1;
      if (fabs_(rr) <= tol * cn) {
        rt.found = 1;
        rt.s = min(max(s + rr / (cn * cn), 0.0f), 1.0f); // the paper's update: s of X's circle
        rt.z = c.c0.z + side * w;
        rt.nrm = VEC3(-c.c0.x, -c.c0.y, side * w) - (rr / (cn * cn)) * c.cd;
        break;
      }
      if (k == 0) dir = rr > 0.0f ? 1.0f : -1.0f;
    }
    if (k == 0 && !(c.w2 >= 0.0f)) break; // (not a phase-1 point)
    if (k == 0 || c.pp < 0.0f) {
      a = s;
      pa = c.pp;
      if (last == 1) pb = 0.5f * pb;
      last = 1;
    } else {
      b = s;
      pb = c.pp;
      have_b = 1;
      if (last == -1) pa = 0.5f * pa;
      last = -1;
    }
    // Predictor: the paper's step, from the cylinder about the tangent line (exact for
    // a straight tube; the bracket catches it where it is not).
    float aa = c.cd.x * c.cd.x + c.cd.y * c.cd.y;
    float sn = s;
    if (aa > 1e-14f * cn * cn) {
      float cxd = c.c0.x * c.cd.y - c.c0.y * c.cd.x;
      float h = fabs_(cxd) / sqrt(aa);
      float hw = sqrt(max((f.r - h) * (f.r + h), 0.0f) / aa) * cn;
      float zeta = side * hw - c.cd.z * c.q1 / aa;
      sn = s + min(max((zeta * c.cd.z - c.q1) / (cn * cn), -0.5f), 0.5f);
    }
    if (have_b == 0) {
      // Outwards until P >= 0: the predictor if it points out, else (or if it stalls)
      // steps that double, starting where the quadratic model of q reaches r^2.
      if ((dir > 0.0f && s >= 1.0f) || (dir < 0.0f && s <= 0.0f)) break; // beyond an end
      if (reach == 0.0f) {
        float qq = dir * c.q1;
        float w2 = max(c.w2, 0.0f);
        float disc = qq * qq + c.q2 * w2;
        float den = qq + sqrt(max(disc, 0.0f));
        reach = den > 0.0f && disc >= 0.0f ? w2 / den : 0.0625f;
        reach = min(max(reach, 1e-6f), 0.0625f);
      } else {
        reach = min(2.0f * reach, 0.5f);
      }
      if (!((sn - s) * dir > 0.0f)) sn = s + dir * reach;
    } else {
      float lo = min(a, b);
      float hi = max(a, b);
      if (!(sn > lo && sn < hi)) sn = c.dp != 0.0f ? s - c.pp / c.dp : s; // Newton on P
      if (!(sn > lo && sn < hi)) sn = (a * pb - b * pa) / (pb - pa);        // Illinois
      if (!(sn > lo && sn < hi) || (k & 3) == 3) sn = 0.5f * (a + b);
    }
    sn = min(max(sn, 0.0f), 1.0f);
    if (!(sn != s)) break;
    s = sn;
  }
  return rt;
}

// Starts of the robust chains: the two most promising local minima of q(s) =
// |C_xy(s)|^2, the squared distance of C(s) from the ray line (the line meets the solid
// iff min q <= r^2). q and q' are sampled at MASQ_CURVE_SEEDS + 1 points; an interval
// where q' goes from - to + holds a minimum (estimated by the secant of q' and the
// parabola through it); an end where q rises inwards is one. A bent curve seen along
// its length can come near the ray more than once, and each end's tangent can point
// away from the nearer approach, so neither the global sample minimum nor the ends
// alone suffice (measured on rays nearly parallel to the curve).
STRUCT_BEGIN(CurveSeeds)
  float s1; // the lowest estimated minimum
  float s2; // the second (-1: none)
STRUCT_END(CurveSeeds)

FN CurveSeeds curve_seeds(CurveFrame f) {
  vec3 a1 = 3.0f * (f.b1 - f.b0);
  vec3 a2 = 3.0f * ((f.b2 - f.b1) - (f.b1 - f.b0));
  vec3 a3 = (f.b3 - f.b0) + 3.0f * (f.b1 - f.b2);
  float h = 1.0f / (MASQ_CURVE_SEEDS * 1.0f);
  float m1 = inf_();
  float m2 = inf_();
  CurveSeeds sd;
  sd.s1 = -1.0f;
  sd.s2 = -1.0f;
  float qp = 0.0f; // q and q'/2 at the previous sample
  float gp = 0.0f;
  float fj = 0.0f; // sample index as a float (no casts in the dialect)
  for (int j = 0; j <= MASQ_CURVE_SEEDS; ++j) {
    float s = fj * h;
    fj += 1.0f;
    float x = f.b0.x + s * (a1.x + s * (a2.x + s * a3.x));
    float y = f.b0.y + s * (a1.y + s * (a2.y + s * a3.y));
    float dx = a1.x + s * (2.0f * a2.x + 3.0f * s * a3.x);
    float dy = a1.y + s * (2.0f * a2.y + 3.0f * s * a3.y);
    float q = x * x + y * y;
    float g = x * dx + y * dy;
    float cs = -1.0f; // candidate minimum in [s - h, s] (or at an end)
    float cq = inf_();
    if (j == 0 && g >= 0.0f) {
      cs = 0.0f;
      cq = q;
    }
    if (j > 0 && gp < 0.0f && g >= 0.0f) {
      float u = gp / (gp - g); // secant root of q' in the interval, in [0, 1]
      cs = s - h + u * h;
      cq = qp + gp * u * h; // parabola: q(a) + q'(a) x / 2
    }
    if (j == MASQ_CURVE_SEEDS && g <= 0.0f && q < cq) {
      cs = 1.0f;
      cq = q;
    }
    if (cs >= 0.0f) {
      if (cq < m1) {
        m2 = m1;
        sd.s2 = sd.s1;
        m1 = cq;
        sd.s1 = cs;
      } else if (cq < m2) {
        m2 = cq;
        sd.s2 = cs;
      }
    }
    qp = q;
    gp = g;
  }
  if (sd.s1 < 0.0f) sd.s1 = 0.5f; // (NaN input)
  return sd;
}

// ---------------------------------------------------------------- both modes

// a*b - c*e as if computed in twice the precision, then rounded (Dot2 of two terms:
// within u |ab - ce| + 4u^2 (|ab| + |ce|)). Built from exact products and TwoSum only,
// not Kahan's fma(a, b, -c*e), which needs a fused fma a GLSL driver may not give (shim.h).
FN float curve_dop(float a, float b, float c, float e) {
  float p = a * b;
  float q = -(c * e);
  float s = p + q;
  float z = s - p;
  return s + (((p - (s - z)) + (q - z)) + (two_prod_err_(a, b, p) - two_prod_err_(c, e, -q)));
}

// dot(a, b) computed as if in twice the precision, then rounded (Ogita, Rump and
// Oishi's Dot2: error-free products (two_prod_err_), sums by TwoSum).
FN float curve_dot_acc(vec3 a, vec3 b) {
  float p = a.x * b.x;
  float cmp = two_prod_err_(a.x, b.x, p);
  float h = a.y * b.y;
  float hq = two_prod_err_(a.y, b.y, h);
  float x = p + h;
  float zz = x - p;
  cmp += ((p - (x - zz)) + (h - zz)) + hq;
  float g = a.z * b.z;
  float gq = two_prod_err_(a.z, b.z, g);
  float y = x + g;
  float zy = y - x;
  cmp += ((x - (y - zy)) + (g - zy)) + gq;
  return y + cmp;
}

FN vec3 curve_cross_acc(vec3 a, vec3 b) {
  return VEC3(curve_dop(a.y, b.z, a.z, b.y), curve_dop(a.z, b.x, a.x, b.z), curve_dop(a.x, b.y, a.y, b.x));
}

FN vec3 curve_to_frame(vec3 w, vec3 ex, vec3 ey, vec3 ez) { return VEC3(dot(w, ex), dot(w, ey), dot(w, ez)); }

// robust != 0: intersect_curve; 0: intersect_curve_fast (see the top of this file).
FN PrimHit curve_intersect_mode(Curve c, vec3 o, vec3 d, float tmin, float tmax, int robust) {
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
  // Exit chains only when the origin (at tlo) may be inside the solid.
  float zlo = (tlo - ts) * dl;
  int maybe_inside = dot(pp, pp) + zlo * zlo <= rb2 ? 1 : 0;
  if (sc > 0.0f && robust != 0) {
    CurveSeeds sd = curve_seeds(f);
    for (int k = 0; k < 4; ++k) {
      float s0 = k == 0 ? sd.s1 : (k == 1 ? sd.s2 : (k == 2 ? 0.0f : 1.0f));
      if (s0 < 0.0f) continue;
      CurveRoot ap = curve_approach(f, s0, MASQ_CURVE_TOL * r, k < 2 ? 1.0f / (MASQ_CURVE_SEEDS * 1.0f) : 0.5f);
      if (ap.found == 0) continue;
      for (int e = 0; e < 2; ++e) {
        if (e == 1 && maybe_inside == 0) break;
        CurveRoot rt = curve_crossing(f, ap.s, e == 0 ? -1.0f : 1.0f, MASQ_CURVE_TOL_CROSS * r);
        if (rt.found != 0) best = prim_take(best, ts + rt.z / dl, tlo, rt.nrm, rt.s);
      }
    }
  }
  if (sc > 0.0f && robust == 0) {
    for (int k = 0; k < 4; ++k) {
      if (k >= 2 && maybe_inside == 0) break;
      float s0 = (k & 1) == 0 ? 0.0f : 1.0f;
      float side = k < 2 ? -1.0f : 1.0f;
      CurveRoot rt = curve_chain_fast(f, s0, side);
      if (rt.found != 0) best = prim_take(best, ts + rt.z / dl, tlo, rt.nrm, rt.s);
    }
  }
  // End balls, outer hemispheres (with an overlap of the tube tolerance at the seam).
  for (int e = 0; e < 2; ++e) {
    vec3 bc = e == 0 ? f.b0 : f.b3;
    if (robust != 0) {
      // The ball centre c from o - c (exact, as o - cen above), not via cen (u L).
      vec3 ce = e == 0 ? p0 : p3;
      vec3 oe = o - ce;
      vec3 be = oe - o;
      vec3 ae = oe - be;
      vec3 le = (o - ae) - (ce + be);
      vec3 pe = cross(d, curve_cross_acc(oe, d) + cross(le, d)) / dd;
      float te = -(curve_dot_acc(oe, d) + dot(le, d)) / dd;
      bc = VEC3(-dot(pe, ex), -dot(pe, ey), (te - ts) * dl);
    }
    vec3 ta = e == 0 ? -f.t0 : f.t1; // outward axis at that end
    float hc = sqrt(bc.x * bc.x + bc.y * bc.y);
    float disc = (r - hc) * (r + hc);
    if (disc >= 0.0f) {
      float q = sqrt(disc);
      float seam = -MASQ_CURVE_TOL * r * sqrt(dot(ta, ta));
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
  return curve_intersect_mode(c, o, d, tmin, tmax, 1);
}

FN PrimHit intersect_curve_fast(Curve c, vec3 o, vec3 d, float tmin, float tmax) {
  return curve_intersect_mode(c, o, d, tmin, tmax, 0);
}

KERNEL_NS_END
#endif
