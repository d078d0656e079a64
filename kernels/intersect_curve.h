// Ray / cubic Bezier curve swept by a sphere of constant radius r (round ends, like
// Embree's round curves): the solid is the union of the balls B(C(s), r), s in [0,1].
// Its boundary is the tube envelope (the circles of radius r perpendicular to C'(s),
// s in [0,1]) plus the outer halves of the end balls at p0 and p3 (for hair-like
// curves: radius of curvature above r, no fold-back within 2r).
//
// Tube: Reshetov & Luebke, "Phantom Ray-Hair Intersector" (HPG 2018). In a ray-centric
// frame (ray = z axis) the cylinder ("cone" with zero slope) with axis C'(s) through
// C(s) is intersected with the ray; the hit's signed distance from the plane through
// C(s) perpendicular to C'(s), over |C'(s)|^2, is the update of s. A fixed point lies on
// the circle of s, i.e. on the envelope. Iterations start once from each end (s = 0
// and s = 1). Entry crossings iterate on the cylinder's near root, exit crossings on
// its far root (needed only when the ray can start inside: rays spawned on or in the
// curve report the exit). End balls: closed-form spheres, kept on their outer
// hemisphere only (the inner one lies inside the tube, so it is no crossing of the
// union). The nearest crossing in [t_lo, tmax] wins.
//
// intersect_curve (robust):
//  - the origin moves to the ray point nearest the curve's centre, computed with an
//    exact o - centre (TwoSum) and an fma-accurate moment (o - centre) x d, so the
//    curve's position across the ray does not carry an error of u * |o - centre|
//    (0.06 r at 10^6 radii away); every later quantity is of the size of the curve;
//  - discriminants as (r - h)(r + h) from the distance h of the ray to the axis;
//  - acceptance when the hit is within 2^-10 r of the normal plane (tolerance scaled
//    to r, not to the parameter); safeguarded secant / Illinois regula falsi steps;
//  - exit iterations whenever the origin may be inside the bounding ball;
//  - self window t_self (prim_hit.h) on every crossing.
// intersect_curve_fast: the paper's loop as written (plain steps clamped to 0.5,
// regula falsi on a sign change with a bisection every 4th iteration, |ds| < 5e-5 in
// curve-parameter units, chain stops when s leaves [0,1]), origin shift by plain
// subtraction, no self window. Both run at most MASQ_CURVE_ITERS curve evaluations per
// chain (the fast one usually stops after fewer: its tolerance is looser).
#ifndef MASQ_KERNEL_INTERSECT_CURVE_H
#define MASQ_KERNEL_INTERSECT_CURVE_H
#include "prim_hit.h"

// GLSL: a specialization constant of that name comes from variants.h.
#if !defined(MASQ_LANG_GLSL)
#ifndef MASQ_CURVE_ITERS
#define MASQ_CURVE_ITERS 8
#endif
#endif

// A fused multiply-add (error-free products) and a guard that keeps GLSL compilers
// from contracting or reordering the error-free transforms.
#if defined(MASQ_LANG_CPP)
#define MASQ_CURVE_FMA(a, b, c) std::fma((a), (b), (c))
#else
#define MASQ_CURVE_FMA(a, b, c) fma((a), (b), (c))
#endif
#if defined(MASQ_LANG_GLSL)
#define MASQ_CURVE_EXACT precise
#else
#define MASQ_CURVE_EXACT
#endif

// Robust acceptance: distance of the hit from the normal plane at C(s), relative to r.
// The cylinder and the tube agree to second order there, so the surface error is about
// kappa * (tol r)^2: nothing at this size. Also the seam overlap of caps and tube.
#define MASQ_CURVE_TOL 9.765625e-4f
// Fast acceptance: the paper's |ds| bound in curve-parameter units.
#define MASQ_CURVE_FAST_TOL 5e-5f
#ifndef MASQ_CURVE_SEEDS
#define MASQ_CURVE_SEEDS 8
#endif

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

// One phantom step at s.
STRUCT_BEGIN(CurveStep)
  int ok;      // tangent usable (not zero, not parallel to the ray)
  int real;    // the ray meets the cylinder at s
  float z;     // the ray's crossing of the cylinder (closest approach if none)
  float g;     // update of s
  float res;   // |g| |C'(s)|: the crossing's distance from the normal plane at C(s)
  vec3 nrm;    // outward normal at the crossing (frame coordinates)
STRUCT_END(CurveStep)

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

// One phantom step at s. side -1: the cylinder's near root (entry), +1: far root (exit).
FN CurveStep curve_step(CurveFrame f, float s, float side) {
  CurvePoint e = curve_eval(f, s);
  vec3 c0 = e.p;
  vec3 cd = e.d;
  CurveStep st;
  st.ok = 0;
  st.real = 0;
  st.z = 0.0f;
  st.g = 0.0f;
  st.res = inf_();
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
  st.res = fabs_(ax) / sqrt(dd2);
  st.nrm = VEC3(-c0.x, -c0.y, zeta) - st.g * cd;
  return st;
}

// Robust chain from s0: Newton steps with the straight-curve slope (s += update, at
// most 0.5) until a sign change of the update brackets the root, then Illinois regula
// falsi (bisection if it leaves the bracket). (A secant slope was tried: it overshoots
// from phantom regions and converged to the wrong crossing more often.)
// s stays in [0,1]; a chain that wants to leave from an end stops (the end ball takes
// over there). Accepts a real crossing within tol (a length) of the normal plane.
FN CurveRoot curve_chain(CurveFrame f, float s0, float side, float tol) {
  CurveRoot rt;
  rt.found = 0;
  rt.z = 0.0f;
  rt.s = s0;
  rt.nrm = VEC3(0.0f, 0.0f, 0.0f);
  float s = s0;
  float sp = s0;
  float gp = 0.0f;
  float a = s0;
  float ga = 0.0f;
  float b = s0;
  float gb = 0.0f;
  int br = 0;
  int rp = 0;
  for (int k = 0; k < MASQ_CURVE_ITERS; ++k) {
    CurveStep st = curve_step(f, s, side);
#ifdef MASQ_CURVE_DEBUG
    if (g_curve_debug) printf("  side %g k %d s %.9g ok %d real %d g %.4g res/r %.4g z %.6g\n", side, k, s, st.ok, st.real, st.g, st.res / f.r, st.z);
#endif
    if (st.ok == 0) break;
    if (st.res <= tol) {
      if (st.real != 0) {
        rt.found = 1;
        rt.z = st.z;
        rt.s = s;
        rt.nrm = st.nrm;
      }
      break; // converged: a crossing, or the closest approach of a miss
    }
    float g = st.g;
    if (br != 0) {
      if (g * gb < 0.0f) {
        a = b;
        ga = gb;
      } else {
        ga = 0.5f * ga;
      }
      b = s;
      gb = g;
    } else if (k > 0 && g * gp < 0.0f) {
      br = 1;
      a = sp;
      ga = gp;
      b = s;
      gb = g;
    }
    float sn;
    if (br != 0) {
      sn = (a * gb - b * ga) / (gb - ga);
      if (!(sn > min(a, b) && sn < max(a, b))) sn = 0.5f * (a + b);
    } else {
      float step = g; // Newton with the straight-curve slope -1
#if AITKEN
      // Monotone linear convergence (same regime, same sign, shrinking): the secant
      // through the last two iterates (Aitken's extrapolation), at most 8 steps' worth.
      if (k > 0 && st.real == rp && g * gp > 0.0f && fabs_(g) < 0.875f * fabs_(gp)) step = g * (s - sp) / (gp - g);
#endif
      sn = s + min(max(step, -0.5f), 0.5f);
    }
    sn = min(max(sn, 0.0f), 1.0f);
    if (sn == s) break;
    sp = s;
    gp = g;
    rp = st.real;
    s = sn;
  }
  return rt;
}

// Robust chain (side -1: entry, +1: exit). The local primitive is the ball at C(s)
// (the swept sphere itself) rather than the paper's cylinder: the ray (z axis) meets it
// at X = (0, 0, C_z + side w), w = sqrt(r^2 - |C_xy|^2), and the residual is the
// paper's, the hit's offset from the normal plane at C(s):
//   R(s) = (X - C(s)) . C'(s) = -q1 + side w C'_z,   q1 = C_xy . C'_xy.
// A root is the phantom fixed point (X on the circle of s, on the envelope). Newton
// uses the exact R' (C'' included), which at the root is the paper's slope -|C'|^2 up to
// the curvature term, while the cylinder's crossing, for a ray running nearly along the
// curve, moves by r / sin(angle) per unit of tilt and sends the paper's step astray.
// Where the ray misses the ball (phantom), Newton on |C_xy|^2 finds the closest
// approach. On an s-interval where the ray is within r, R > 0 at its left end and
// R < 0 at its right end, so a real point with R > 0 and any later point with R < 0 or
// outside the interval bracket a root: then Illinois regula falsi, or bisection.
FN CurveRoot curve_chain_ball(CurveFrame f, float s0, float side, float tol) {
  CurveRoot rt;
  rt.found = 0;
  rt.z = 0.0f;
  rt.s = s0;
  rt.nrm = VEC3(0.0f, 0.0f, 0.0f);
  float s = s0;
  float r = f.r;
  float lo = -1.0f; // bracket: R > 0 (or phantom) at lo, R < 0 (or phantom) at hi
  float hi = 2.0f;
  float rlo = 0.0f; // R there, 0 for a phantom end
  float rhi = 0.0f;
  int last = 0;     // which end moved last (+1 lo, -1 hi), for Illinois
  for (int k = 0; k < MASQ_CURVE_ITERS; ++k) {
    CurvePoint e = curve_eval(f, s);
    vec3 c0 = e.p;
    vec3 cd = e.d;
    vec3 c2 = e.dd;
    float d2 = dot(cd, cd);
    float dxy = cd.x * cd.x + cd.y * cd.y;
    float q1 = c0.x * cd.x + c0.y * cd.y;        // |C_xy|^2' / 2
    float q2 = dxy + c0.x * c2.x + c0.y * c2.y; // |C_xy|^2'' / 2
    float rho = sqrt(c0.x * c0.x + c0.y * c0.y);
    float w2 = (r - rho) * (r + rho);
    float ds;
    int real = w2 >= 0.0f ? 1 : 0;
    if (real != 0) {
      float w = sqrt(w2);
      float rr = side * w * cd.z - q1;
      float res = fabs_(rr) / sqrt(d2);
#ifdef MASQ_CURVE_DEBUG
      if (g_curve_debug) printf("  ball side %g k %d s %.9g real w/r %.4g res/r %.4g z %.6g [%g %g]\n", side, k, s, w / r, res / r, c0.z + side * w, lo, hi);
#endif
      if (res <= tol) {
        rt.found = 1;
        rt.z = c0.z + side * w;
        rt.s = s;
        rt.nrm = VEC3(-c0.x, -c0.y, side * w) - (rr / d2) * cd;
        break;
      }
      if (rr > 0.0f) {
        if (s > lo) {
          lo = s;
          rlo = rr;
          if (last == 1) rhi = 0.5f * rhi;
          last = 1;
        }
      } else if (s < hi) {
        hi = s;
        rhi = rr;
        if (last == -1) rlo = 0.5f * rlo;
        last = -1;
      }
      float dr = side * (w * c2.z - (q1 / w) * cd.z) - q2; // R'
      ds = dr < 0.0f ? -rr / dr : rr / d2;
    } else {
#ifdef MASQ_CURVE_DEBUG
      if (g_curve_debug) printf("  ball side %g k %d s %.9g phantom rho/r %.4g [%g %g]\n", side, k, s, rho / r, lo, hi);
#endif
      // A phantom point beyond a real end closes the bracket on that end's side.
      if (lo >= 0.0f && s > lo && s < hi) {
        hi = s;
        rhi = 0.0f;
        last = -1;
      } else if (hi <= 1.0f && s < hi && s > lo) {
        lo = s;
        rlo = 0.0f;
        last = 1;
      }
      ds = q2 > 0.0f ? -q1 / q2 : (q1 > 0.0f ? -0.125f : 0.125f); // closest approach
      if (!(lo >= 0.0f && hi <= 1.0f) && fabs_(ds) * sqrt(d2) <= tol) break; // converged: a miss
    }
    float sn = s + min(max(ds, -0.5f), 0.5f);
    if (lo >= 0.0f && hi <= 1.0f) { // bracketed
      if (rlo != 0.0f && rhi != 0.0f) sn = (lo * rhi - hi * rlo) / (rhi - rlo);
      if (!(sn > lo && sn < hi) || (k & 3) == 3) sn = 0.5f * (lo + hi);
    }
    sn = min(max(sn, 0.0f), 1.0f);
    if (!(sn != s)) break; // stuck at an end (or NaN)
    s = sn;
  }
  return rt;
}

// Third start of the robust chains: the sample (of MASQ_CURVE_SEEDS + 1) where the
// curve passes closest to the ray line (smallest |C_xy(s)|). The line meets the solid
// iff min_s |C_xy(s)| <= r, so the crossings are near there, wherever the ends'
// tangents point (from an end, a bent curve can send the iteration the wrong way).
FN float curve_seed(CurveFrame f) {
  vec3 a1 = 3.0f * (f.b1 - f.b0);
  vec3 a2 = 3.0f * ((f.b2 - f.b1) - (f.b1 - f.b0));
  vec3 a3 = (f.b3 - f.b0) + 3.0f * (f.b1 - f.b2);
  float h = 1.0f / (MASQ_CURVE_SEEDS * 1.0f);
  float qm = inf_();
  float sm = 0.0f;
  float fj = 0.0f; // sample index as a float (no casts in the dialect)
  for (int j = 0; j <= MASQ_CURVE_SEEDS; ++j) {
    float s = fj * h;
    fj += 1.0f;
    float x = f.b0.x + s * (a1.x + s * (a2.x + s * a3.x));
    float y = f.b0.y + s * (a1.y + s * (a2.y + s * a3.y));
    float q = x * x + y * y;
    if (q < qm) {
      qm = q;
      sm = s;
    }
  }
  return sm;
}

// The paper's chain: steps clamped to 0.5; on a sign change regula falsi between the
// last two iterates, bisection every 4th iteration; stops when s leaves [0,1].
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

// a*b - c*e to within 1.5 ulp (Kahan's algorithm with fma).
FN float curve_dop(float a, float b, float c, float e) {
  MASQ_CURVE_EXACT float w = c * e;
  MASQ_CURVE_EXACT float err = MASQ_CURVE_FMA(-c, e, w);
  MASQ_CURVE_EXACT float fa = MASQ_CURVE_FMA(a, b, -w);
  return fa + err;
}

FN vec3 curve_cross_acc(vec3 a, vec3 b) {
  return VEC3(curve_dop(a.y, b.z, a.z, b.y), curve_dop(a.z, b.x, a.x, b.z), curve_dop(a.x, b.y, a.y, b.x));
}

FN PrimHit curve_take(PrimHit best, float t, float tlo, vec3 nrm, float u) {
  if (t >= tlo && t <= best.t) {
    best.hit = 1;
    best.t = t;
    best.normal = nrm;
    best.u = u;
    best.v = 0.0f;
  }
  return best;
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
  MASQ_CURVE_EXACT vec3 oc = o - cen;
  vec3 pp;
  float ts;
  if (robust != 0) {
    // o - cen = oc + ol exactly (TwoSum); moment (o - cen) x d to ~1 ulp; then
    // pp = d x ((o - cen) x d) / dd has an error of the size of u |pp|, not u |o - cen|.
    MASQ_CURVE_EXACT vec3 bv = oc - o;
    MASQ_CURVE_EXACT vec3 av = oc - bv;
    MASQ_CURVE_EXACT vec3 ol = (o - av) - (cen + bv);
    vec3 mom = curve_cross_acc(oc, d) + cross(ol, d);
    pp = cross(d, mom) / dd;
    ts = -(dot(oc, d) + dot(ol, d)) / dd;
  } else {
    ts = -dot(oc, d) / dd;
    pp = oc + ts * d;
  }
  if (!(dot(pp, pp) <= rb2)) return prim_miss(); // misses the bounding ball (or NaN)
  float tlo = robust != 0 ? max(tmin, self_eps_t(r, oc, dd)) : tmin;
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
#ifdef MASQ_CURVE_DEBUG
  if (g_curve_debug) printf(" robust %d ts %g dl %g zlo %g inside %d r %g b0 %g %g %g b3 %g %g %g\n", robust, ts, dl, zlo, maybe_inside, r, f.b0.x, f.b0.y, f.b0.z, f.b3.x, f.b3.y, f.b3.z);
#endif
  if (sc > 0.0f && robust != 0) {
    float sd = curve_seed(f);
    for (int k = 0; k < 6; ++k) {
      if (k >= 3 && maybe_inside == 0) break;
      float s0 = k % 3 == 0 ? sd : (k % 3 == 1 ? 0.0f : 1.0f);
      float side = k < 3 ? -1.0f : 1.0f;
#if BALL
      CurveRoot rt = curve_chain_ball(f, s0, side, MASQ_CURVE_TOL * r);
#else
      CurveRoot rt = curve_chain(f, s0, side, MASQ_CURVE_TOL * r);
#endif
      if (rt.found != 0) best = curve_take(best, ts + rt.z / dl, tlo, rt.nrm, rt.s);
    }
  }
  if (sc > 0.0f && robust == 0) {
    for (int k = 0; k < 4; ++k) {
      if (k >= 2 && maybe_inside == 0) break;
      float s0 = (k & 1) == 0 ? 0.0f : 1.0f;
      float side = k < 2 ? -1.0f : 1.0f;
      CurveRoot rt = curve_chain_fast(f, s0, side);
      if (rt.found != 0) best = curve_take(best, ts + rt.z / dl, tlo, rt.nrm, rt.s);
    }
  }
  // End balls, outer hemispheres (with an overlap of the tube tolerance at the seam).
  for (int e = 0; e < 2; ++e) {
    vec3 bc = e == 0 ? f.b0 : f.b3;
    vec3 ta = e == 0 ? -f.t0 : f.t1; // outward axis at that end
    float hc = sqrt(bc.x * bc.x + bc.y * bc.y);
    float disc = (r - hc) * (r + hc);
    if (disc >= 0.0f) {
      float q = sqrt(disc);
      float seam = -MASQ_CURVE_TOL * r * sqrt(dot(ta, ta));
      for (int k = 0; k < 2; ++k) {
        float z = k == 0 ? bc.z - q : bc.z + q;
        vec3 w = VEC3(-bc.x, -bc.y, z - bc.z);
        if (dot(w, ta) >= seam) best = curve_take(best, ts + z / dl, tlo, w, e == 0 ? 0.0f : 1.0f);
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
