// Ray/round cone (Han et al.'s "link": the convex hull of the spheres (a, ra), (b, rb)),
// robust and fast.
//
// Geometry. Axis w = (b-a)/L, axial coordinate z from a, radial distance rho. The
// lateral surface is the cone tangent to both spheres. Its outward normal in a
// meridian plane is n = (cos th, sin th) in (rho, z), with sin th = (ra - rb)/L (th > 0:
// the cone narrows towards b). The tangent line satisfies n.(x - a) = ra, and indeed
// n.(b - a) + rb = L sin th + rb = ra, so the lateral surface is
//     rho cos th + z sin th = ra,
// touching sphere a at z = za = ra sin th and sphere b at z = zb = L + rb sin th (the
// points a + ra n and b + rb n). Between them it is the surface; sphere a is exposed
// for z <= za, sphere b for z >= zb. On [za, zb], ra - z sin th >= rb cos^2 th >= 0,
// so the range test also rejects the cone's other nappe. L <= |ra - rb|: one sphere
// contains the other and the primitive is the bigger sphere.
//
// Robust form (the ideas of the robust capsule):
//  1. origin relative to the nearer ball centre (o - a or o - b: one rounding of a
//     difference of inputs), then shifted along the ray to its closest approach p to
//     it: every quantity is of the size of the primitive, not of its distance (8.);
//  2. axis frame: p = pr + pa w, d = dr + da w (pr, dr radial); with c = cos th,
//     s = sin th, k = ra - s z0 (z0: axial coordinate of p from a), m = s da, the
//     side is c^2 |pr + t dr|^2 = (k - m t)^2, i.e. A t^2 + 2 B t + C = 0 with
//       A = (c|dr| - m)(c|dr| + m),  B = c^2 pr.dr + k m,  C = (c|pr| - k)(c|pr| + k);
//  3. the discriminant in factored form: expanding,
//       B^2 - A C = c^2 (|k dr + m pr|^2 - c^2 |pr x dr|^2)
//                 = c^2 (X - c Y)(X + c Y),  X = |k dr + m pr|,  Y = |pr x dr|,
//     which holds at any origin on the ray (for m = 0, s = 0 it is the capsule's
//     (r - |v|)(r + |v|) |dr|^2); X - cY is the genuine silhouette quantity, not a
//     difference of two squares of the size of the primitive's length;
//  4. stable roots q = -(B + sign(B) sqrt(disc)), s0 = q/A, s1 = C/q. Where the ray
//     is inside the solid cone is read off the sign of A, not from tests on the
//     roots: A > 0, between the roots; A < 0 (a ray steeper than the cone meets both
//     nappes), the half-line on the slab's nappe, s <= both roots if m > 0 (k - m s
//     grows towards s = -inf) and s >= both if m < 0; A = 0, the half-line where
//     2 B s + C <= 0. So a root that passes infinity as A changes sign (a ray parallel
//     to a generator) or a pair that meets at the apex (a ray through the point end
//     of rb = 0) changes nothing discontinuously;
//  5. pieces as intervals, not as surface patches. The solid is the union of three
//     convex pieces: the truncated solid cone T = {inside the cone, za <= z <= zb} and
//     the two balls. The ray's interval in T is the slab's interval [(za - z0)/da,
//     (zb - z0)/da] cut by the cone's; each ball gives its chord. The solid is convex,
//     so its interval is [min, max] of the three, and its entry (or, from inside, its
//     exit) is the hit. No range test on a root's z: for a ray nearly parallel to the
//     axis z is ill-conditioned (a lateral rounding error e moves it by e / angle, up
//     to r at L/r = 1e4), and near a tangency circle such a test rejected side roots
//     while the grazed sphere was missed too, losing rays that clearly cross the
//     solid. Clipped by the slab, T's interval ends on the slab plane instead, inside
//     the ball, so a ball missed by rounding leaves an end within rounding of the
//     surface;
//  6. the normal is chosen by where the point lies (z <= za: ball a, z >= zb: ball b,
//     else the side), not by which piece's crossing was nearest: near a tangency
//     circle the pieces' crossings agree to second order in the distance from it, so
//     the nearest is a coin toss there while the normals differ to first order;
//  7. dot(d,d) carried; the self-intersection window applied (prim_hit.h; centre =
//     midpoint of a and b, r = max(ra, rb));
//  8. each ball solved relative to its own centre, and the lateral surface relative to
//     the ball centre the ray passes nearer (items 1.-5. with p the ray's closest
//     approach to that centre): near an end the error is u (D + r), not u (D + L).
// Fast: Quilez's "rounded cone" intersector (iquilezles.org) as written, adapted to
// non-unit d (dd in the t^2 terms), both roots and exposure tests for the spheres (a
// ray starting inside reports its exit), and the contained-sphere case.
#ifndef MASQ_KERNEL_INTERSECT_ROUND_CONE_H
#define MASQ_KERNEL_INTERSECT_ROUND_CONE_H
#include "prim_hit.h"
#include "intersect_capsule.h"
#include "intersect_sphere.h"

KERNEL_NS_BEGIN

// Axial parameter of a hit at axial coordinate z (from a): clamped to [0, 1].
FN float cone_u(float z, float len) { return min(max(z / len, 0.0f), 1.0f); }

FN PrimHit intersect_round_cone(RoundCone rc, vec3 o, vec3 d, float tmin, float tmax) {
  float ra = rc.ra;
  float rb = rc.rb;
  float dd = dot(d, d);
  // No ray or an empty/NaN interval: miss. Negative and NaN radii count as 0 (a point
  // end; both 0: no surface), as in the oracle.
  if (!(dd > 0.0f) || !(tmin <= tmax)) return prim_miss();
  ra = ra > 0.0f ? ra : 0.0f;
  rb = rb > 0.0f ? rb : 0.0f;
  float rmax = max(ra, rb);
  if (!(rmax > 0.0f)) return prim_miss();
  vec3 a = V3(rc.a);
  vec3 ba = V3(rc.b) - a;
  vec3 oa = o - a;
  vec3 oc = oa - 0.5f * ba;
  float tlo = max(tmin, self_eps_t_span(rmax, oc, length(ba), dd));
  float len = length(ba);
  if (!(len > fabs_(ra - rb))) {
    // One sphere contains the other (or zero length): the bigger sphere.
    PrimHit hs = sphere_hit_robust(ra >= rb ? oa : o - V3(rc.b), rmax, d, dd, tlo, tmax);
    hs.u = ra >= rb ? 0.0f : 1.0f;
    return hs;
  }
  vec3 w = ba / len;
  float sn = (ra - rb) / len;
  float cs = sqrt(max((1.0f - sn) * (1.0f + sn), 0.0f)); // |sn| < 1 unless division rounds up
  float za = ra * sn;
  float zb = len + rb * sn;

  // 1. closest approach to each ball's centre (8.); the lateral surface is solved from
  // the nearer one's: t = ts + s.
  vec3 ob = o - V3(rc.b);
  float ta = -dot(oa, d) / dd;
  float tb = -dot(ob, d) / dd;
  vec3 xa = oa + ta * d;
  vec3 xb = ob + tb * d;
  int near_b = dot(xb, xb) < dot(xa, xa) ? 1 : 0;
  float ts = near_b != 0 ? tb : ta;
  vec3 p = near_b != 0 ? xb : xa;
  float pa = dot(p, w); // axial coordinate from that centre
  float da = dot(d, w);
  float z0 = near_b != 0 ? pa + len : pa; // from a: where the point lies (normal, u)
  // 2.-4. lateral surface; k = ra - sn z0 = rb - sn (z0 - len), from the frame's end.
  vec3 pr = p - pa * w;
  vec3 dr = d - da * w;
  float k = near_b != 0 ? rb - sn * pa : ra - sn * pa;
  float m = sn * da;
  float lpr = length(pr);
  float ldr = length(dr);
  float qa = (cs * ldr - m) * (cs * ldr + m);
  float qb = cs * cs * dot(pr, dr) + k * m;
  float qc = (cs * lpr - k) * (cs * lpr + k);
  float X = length(k * dr + m * pr);
  float Y = length(cross(pr, dr));
  float disc = (X - cs * Y) * (X + cs * Y);
  // 5. the ray's interval [lo, hi] (in s) in the truncated solid cone T: the slab
  // za <= z <= zb cut down to where f = A s^2 + 2 B s + C <= 0 (on the slab that is
  // inside the solid cone: the apex, z = ra / s, lies outside [za, zb]).
  float lo = -inf_();
  float hi = inf_();
  // A > 0 and disc < 0: the line misses the cone. A <= 0 and disc < 0 is impossible
  // (the line would lie inside both nappes without passing the apex): a ray through
  // the apex, rounded; it is taken as passing it (disc = 0).
  bool in_t = disc >= 0.0f || qa <= 0.0f;
  if (da != 0.0f) {
    // The slab's planes from the frame's end: the nearer one without the length.
    float sa = (near_b != 0 ? (za - len) - pa : za - pa) / da;
    float sb = (near_b != 0 ? rb * sn - pa : zb - pa) / da;
    lo = min(sa, sb);
    hi = max(sa, sb);
  } else {
    in_t = in_t && z0 >= za && z0 <= zb;
  }
  if (in_t) {
    float sq = cs * sqrt(max(disc, 0.0f));
    float q = -(qb + (qb >= 0.0f ? sq : -sq));
    float r1 = q != 0.0f ? qc / q : 0.0f;
    if (qa != 0.0f) {
      float r0 = q / qa; // q = 0 (B = 0, AC = 0): the double root 0
      if (qa > 0.0f) {
        // f <= 0 between the roots.
        lo = max(lo, min(r0, r1));
        hi = min(hi, max(r0, r1));
      } else if (m > 0.0f) {
        // A < 0 (the ray is steeper than the cone: f <= 0 outside the roots, one
        // half-line in each nappe); m > 0: k - m s > 0 as s -> -inf, the slab's nappe.
        hi = min(hi, min(r0, r1));
      } else {
        lo = max(lo, max(r0, r1));
      }
    } else if (qb > 0.0f) {
      hi = min(hi, r1); // A = 0 (parallel to a generator): f = 2 B s + C
    } else if (qb < 0.0f) {
      lo = max(lo, r1);
    } else {
      in_t = qc <= 0.0f; // f = C: along a cylinder's axis (sn = 0, dr = 0)
    }
  }
  // Union with the two balls: the solid is convex, so its interval is [min, max] of the
  // pieces' intervals (each piece lies inside the solid: no exposure tests needed).
  float s_in = inf_();
  float s_out = -inf_();
  if (in_t && lo <= hi) {
    s_in = lo;
    s_out = hi;
  }
  // Each ball is solved relative to its own centre (origin o - a or o - b, shifted to
  // the closest approach to it), as the capsule's caps: through p its distance from the
  // ray would carry the centre frame's rounding, u (D + L), instead of u (D + r). Only
  // its chord's position along the ray goes through te - ts (an error along the ray).
  for (int e = 0; e < 2; ++e) {
    float rs = e == 0 ? ra : rb;
    float te = e == 0 ? ta : tb;
    vec3 pc = e == 0 ? xa : xb;
    BallSpan b = ball_span(pc, rs, d, dd);
    if (rs > 0.0f && b.found != 0) {
      float s0 = b.s0;
      float sq = b.q;
      float sh = te - ts;
      s_in = min(s_in, sh + (s0 - sq));
      s_out = max(s_out, sh + (s0 + sq));
    }
  }
  // Nearest boundary crossing in the window: the entry, or the exit from inside.
  PrimHit res = prim_miss();
  if (!(s_in <= s_out)) return res;
  float t_in = ts + s_in;
  float t_out = ts + s_out;
  bool take_in = t_in >= tlo && t_in <= tmax;
  if (!take_in && !(t_out >= tlo && t_out <= tmax)) return res;
  float s = take_in ? s_in : s_out;
  float z = z0 + s * da;
  // 6. the normal of the surface part the point lies on, chosen by z (near a seam the
  // pieces' crossings nearly coincide, so which piece gave s says little).
  vec3 nrm;
  if ((z <= za && ra > 0.0f) || (z >= zb && rb > 0.0f)) {
    // A ball's normal, relative to its own centre (8.).
    float te = z <= za ? ta : tb;
    nrm = (z <= za ? xa : xb) + ((ts - te) + s) * d;
  } else {
    vec3 xr = pr + s * dr;
    nrm = cs * xr + (sn * length(xr)) * w;
  }
  if (!(dot(nrm, nrm) > 0.0f)) nrm = z >= zb ? w : -w; // on the axis at a point end
  res.hit = 1;
  res.t = take_in ? t_in : t_out;
  res.normal = nrm;
  res.u = cone_u(z, len);
  return res;
}

// Quilez's rounded cone. y = ba.(oa + t d) - ra rr is 0 on the tangency circle of
// sphere a and d2 = |ba|^2 - rr^2 on that of sphere b.
FN PrimHit intersect_round_cone_fast(RoundCone rc, vec3 ro, vec3 rd, float tmin, float tmax) {
  float ra = rc.ra;
  float rb = rc.rb;
  ra = ra > 0.0f ? ra : 0.0f;
  rb = rb > 0.0f ? rb : 0.0f;
  if (!(max(ra, rb) > 0.0f)) return prim_miss();
  vec3 pa = V3(rc.a);
  vec3 pb = V3(rc.b);
  vec3 ba = pb - pa;
  vec3 oa = ro - pa;
  vec3 ob = ro - pb;
  float dd = dot(rd, rd);
  float rr = ra - rb;
  float m0 = dot(ba, ba);
  float d2 = m0 - rr * rr;
  if (!(d2 > 0.0f)) // one sphere contains the other: the bigger one
    return sphere_hit_fast(ra >= rb ? oa : ob, max(ra, rb), rd, dd, tmin, tmax);
  float m1 = dot(ba, oa);
  float m2 = dot(ba, rd);
  float m3 = dot(rd, oa);
  float m5 = dot(oa, oa);
  float m6 = dot(ob, rd);
  float m7 = dot(ob, ob);
  PrimHit res = prim_miss();
  res.t = tmax;
  // body
  float k2 = d2 * dd - m2 * m2;
  float k1 = d2 * m3 - m1 * m2 + m2 * rr * ra;
  float k0 = d2 * m5 - m1 * m1 + m1 * rr * ra * 2.0f - m0 * ra * ra;
  float h = k1 * k1 - k0 * k2;
  if (h < 0.0f) return prim_miss(); // the spheres lie inside the infinite cone
  float sh = sqrt(h);
  for (int j = 0; j < 2; ++j) {
    float t = (j == 0 ? -sh - k1 : sh - k1) / k2;
    float y = m1 - ra * rr + t * m2;
    if (y > 0.0f && y < d2)
      res = prim_take(res, t, tmin, d2 * (oa + t * rd) - ba * y, cone_u(y + ra * rr, m0));
  }
  // caps
  float h1 = m3 * m3 - dd * (m5 - ra * ra);
  float h2 = m6 * m6 - dd * (m7 - rb * rb);
  for (int e = 0; e < 2; ++e) {
    float hc = e == 0 ? h1 : h2;
    float bc = e == 0 ? m3 : m6;
    if (hc > 0.0f) {
      float shc = sqrt(hc);
      for (int j = 0; j < 2; ++j) {
        float t = (j == 0 ? -bc - shc : -bc + shc) / dd;
        float y = m1 - ra * rr + t * m2;
        if (e == 0 ? y <= 0.0f : y >= d2)
          res = prim_take(res, t, tmin, (e == 0 ? oa : ob) + t * rd, cone_u(y + ra * rr, m0));
      }
    }
  }
  if (res.hit == 0) return prim_miss();
  return res;
}
KERNEL_NS_END
#endif
