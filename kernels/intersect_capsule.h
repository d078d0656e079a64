// Ray/capsule (constant-radius segment with spherical caps), robust form.
// Quilez's closed form loses most of its digits for thin, long or distant capsules
// (measured: 29-44% wrong silhouette rays at r = 1e-4). This version
//  1. moves the origin to the ray's closest approach to an ENDPOINT (o - a or o - b:
//     one rounding of a difference of inputs, so no error proportional to the distance
//     of the capsule from the world origin), so every later quantity is of the size of
//     the ray's distance from that endpoint, not of the distance travelled;
//  2. solves each end ball in its own endpoint's frame, and the side in the frame of
//     the endpoint the ray passes nearer: a crossing near an end then carries
//     u (D + r), not u (D + L) (the rounding of a centre frame L/2 away; issue 23
//     measured false cap hits up to 0.12 r outside at L = 1e6 r; docs/robustness.md);
//  3. works in the capsule's axis frame for the side: the axial parts of origin and
//     direction are removed, leaving a 2D circle problem;
//  4. forms each discriminant as (r-|v|)(r+|v|) from the closest-approach vector v,
//     instead of b^2 - c, which cancels catastrophically;
//  5. takes pieces as intervals, not surface patches (as the round cone): the capsule
//     is the union of the finite cylinder (the infinite one's interval cut by the slab
//     between the end planes) and the two balls, convex, so its interval is [min, max]
//     of theirs and no crossing is tested against a seam. A hemisphere or end-plane
//     test is ill-conditioned for a ray nearly parallel to the axis (its crossing's
//     axial position carries e / angle), and a tolerance on it either opens a gap or,
//     relative to the length, accepted side crossings up to e^2 / 2r = 0.12 r outside
//     the cap at L = 1e6 r. The normal is chosen by where the point lies;
//  6. carries dot(d,d), so non-unit and transformed directions give exact t;
//  7. ignores crossings closer than the self-intersection window t_self (prim_hit.h).
#ifndef MASQ_KERNEL_INTERSECT_CAPSULE_H
#define MASQ_KERNEL_INTERSECT_CAPSULE_H
#include "prim_hit.h"

KERNEL_NS_BEGIN

FN PrimHit intersect_capsule(Capsule cap, vec3 o, vec3 d, float tmin, float tmax) {
  PrimHit res = prim_miss();
  res.t = tmax;
  float r = cap.radius;
  float dd = dot(d, d);
  // Zero/negative/NaN radius (no surface), no ray, or an empty/NaN interval: miss.
  if (!(r > 0.0f) || !(dd > 0.0f) || !(tmin <= tmax)) return prim_miss();
  vec3 a = V3(cap.a);
  vec3 b = V3(cap.b);
  vec3 ba = b - a;
  float len = length(ba);
  float h = 0.5f * len;
  vec3 w = len > 0.0f ? ba / len : VEC3(0.0f, 0.0f, 1.0f);
  // 7. self window, from the origin relative to the centre.
  vec3 oc = (o - a) - 0.5f * ba;
  float tlo = max(tmin, self_eps_t_span(r, oc, len, dd));
  // 1. the ray point nearest each endpoint: t = te + s.
  vec3 oa = o - a;
  vec3 ob = o - b;
  float ta = -dot(oa, d) / dd;
  float tb = -dot(ob, d) / dd;
  vec3 pa = oa + ta * d;
  vec3 pb = ob + tb * d;
  float da = dot(d, w);
  // 5. the ray's interval [t_in, t_out] in the solid: the union of the pieces'. Each
  // end also keeps its frame (0: a, 1: b) and s, the parameter within it (t = te + s),
  // for the normal: t - te would round like t, u (D / |d|).
  float t_in = inf_();
  float t_out = -inf_();
  float s_in = 0.0f;
  float s_out = 0.0f;
  int e_in = 0;
  int e_out = 0;
  // Balls, each in its endpoint's frame.
  for (int e = 0; e < 2; ++e) {
    vec3 pe = e == 0 ? pa : pb;
    float te = e == 0 ? ta : tb;
    BallSpan ball = ball_span(pe, r, d, dd);
    if (ball.found != 0) {
      float s0 = ball.s0;
      float q = ball.q;
      float t0 = te + (s0 - q);
      float t1 = te + (s0 + q);
      if (t0 < t_in) {
        t_in = t0;
        s_in = s0 - q;
        e_in = e;
      }
      if (t1 > t_out) {
        t_out = t1;
        s_out = s0 + q;
        e_out = e;
      }
    }
  }
  // 2./3./4. the finite cylinder in the axis frame of the nearer endpoint: z, the axial
  // coordinate from it, spans [0, len] (a) or [-len, 0] (b). A ray parallel to the axis
  // (dr = 0) is covered by the balls: its interval runs from one to the other.
  int near_b = dot(pb, pb) < dot(pa, pa) ? 1 : 0;
  vec3 pn = near_b != 0 ? pb : pa;
  float tn = near_b != 0 ? tb : ta;
  float pz = dot(pn, w);
  vec3 pr = pn - pz * w;
  vec3 dr = d - da * w;
  float drdr = dot(dr, dr);
  if (h > 0.0f && drdr > 0.0f) {
    BallSpan c = ball_span(pr, r, dr, drdr);
    if (c.found != 0) {
      float lo = c.s0 - c.q;
      float hi = c.s0 + c.q;
      float zlo = near_b != 0 ? -len : 0.0f;
      float zhi = near_b != 0 ? 0.0f : len;
      if (da != 0.0f) {
        float sa = (zlo - pz) / da;
        float sb = (zhi - pz) / da;
        lo = max(lo, min(sa, sb));
        hi = min(hi, max(sa, sb));
      } else if (!(pz >= zlo && pz <= zhi)) {
        lo = inf_();
      }
      if (lo <= hi) {
        if (tn + lo < t_in) {
          t_in = tn + lo;
          s_in = lo;
          e_in = near_b;
        }
        if (tn + hi > t_out) {
          t_out = tn + hi;
          s_out = hi;
          e_out = near_b;
        }
      }
    }
  }
  // The entry, or (from inside) the exit, within the window.
  if (!(t_in <= t_out)) return prim_miss();
  int take_in = t_in >= tlo && t_in <= tmax ? 1 : 0;
  if (take_in == 0 && !(t_out >= tlo && t_out <= tmax)) return prim_miss();
  int e = take_in != 0 ? e_in : e_out;
  float sh = take_in != 0 ? s_in : s_out;
  // The normal of the part the point lies on, by its axial coordinate from its frame's
  // endpoint (near a seam the pieces' crossings agree to second order, so which piece
  // gave t says little); past the other end (by rounding only), that ball's.
  vec3 x = (e != 0 ? pb : pa) + sh * d;
  float z = dot(x, w);
  float zn = e != 0 ? z : -z; // >= 0: beyond this frame's end
  vec3 nrm = x - z * w;
  float u = e != 0 ? 1.0f + z / len : z / len;
  if (zn >= 0.0f || h == 0.0f) {
    nrm = x;
    u = e != 0 ? 1.0f : 0.0f;
  } else if (zn <= -len) {
    nrm = e != 0 ? x + ba : x - ba;
    u = e != 0 ? 0.0f : 1.0f;
  }
  res.hit = 1;
  res.t = take_in != 0 ? t_in : t_out;
  res.normal = nrm;
  res.u = min(max(u, 0.0f), 1.0f);
  if (res.hit == 0) return prim_miss();
  return res;
}
KERNEL_NS_END
#endif
