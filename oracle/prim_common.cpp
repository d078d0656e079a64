// The helpers every primitive's oracle uses (prim_common.h), and the self window of
// the oracle_prims.h contract.
#include "oracle/prim_common.h"
#include "oracle/solve.h"

namespace masq::oracle {

ld self_window_t(ld radius, Vld o_minus_centre, ld dd, ld span) {
  const ld rel = 1.0L / 1024, u = 1.0L / 16777216;
  return (rel * std::max<ld>(radius, 0) + 32 * u * (detail::len(o_minus_centre) + span)) / std::sqrt(dd);
}

namespace detail {

namespace {

// argmin over s in [0,1] of |u0 + s u1| + k s: convex (a norm of an affine function
// plus a linear term). Unconstrained, |u0 + s u1| = sqrt(A x^2 + h^2) with A = |u1|^2,
// x = s - s0 (s0 the foot of the perpendicular, h its distance); the derivative
// A x / sqrt(A x^2 + h^2) + k vanishes at x = -k h / sqrt(A (A - k^2)) when k^2 < A, and
// otherwise has the sign of k throughout.
ld argmin_norm_plus_linear(Vld u0, Vld u1, ld k) {
  ld A = dot(u1, u1);
  if (A == 0 || k * k >= A) return k > 0 ? 0 : (k < 0 ? 1 : 0);
  ld s0 = -dot(u0, u1) / A;
  if (k == 0) return clamp01(s0);
  return clamp01(s0 - k * len(u0 + s0 * u1) / std::sqrt(A * (A - k * k)));
}

} // namespace

bool valid(const PrimRay& r) {
  return finite(r.o) && finite(r.d) && dot(r.d, r.d) > 0 && !std::isnan(r.tmin) && !std::isnan(r.tmax) &&
         r.tmin <= r.tmax && r.tmin < kInf;
}

ld window_lo(const PrimRay& ray, ld r, Vld centre, ld span) {
  return std::max(ray.tmin, self_window_t(r, ray.o - centre, dot(ray.d, ray.d), span));
}

bool gap_clear(ld gap, ld r) { return gap > 1e-8L * r; }

void select(const Bound* b, int n, ld lo, ld tmax, PrimResult& res) {
  for (int i = 0; i < n && b[i].t <= tmax; ++i)
    if (b[i].t >= lo) {
      res.hit = true;
      res.t = b[i].t;
      res.normal = unit(b[i].n);
      res.u = b[i].u;
      return;
    }
}

void select_hull(const Hull& h, const PrimRay& ray, ld r, Vld centre, ld span, PrimResult& res) {
  if (!h.any) return;
  Bound b[2] = {h.in, h.out};
  select(b, 2, window_lo(ray, r, centre, span), ray.tmax, res);
}

Based base_at(Vld o, Vld d, Vld c) {
  ld t0 = dot(c - o, d) / dot(d, d);
  return {o + t0 * d, t0};
}

Based base_at_axis(Vld o, Vld d, Vld a, Vld w, ld ylo, ld yhi) {
  Based b = base_at(o, d, a + (0.5L * (ylo + yhi)) * w);
  Vld x = b.o - a;
  ld y = dot(x, w), dw = dot(d, w);
  Vld xp = x - y * w, dp = d - dw * w;
  ld dp2 = dot(dp, dp);
  if (dp2 == 0) return b;
  ld tau = -dot(xp, dp) / dp2;
  if (dw != 0) {
    ld t1 = (ylo - y) / dw, t2 = (yhi - y) / dw;
    tau = std::clamp(tau, std::min(t1, t2), std::max(t1, t2));
  }
  return {b.o + tau * d, b.t0 + tau};
}

int sphere_roots(Vld c, ld r, Vld o, Vld d, ld out[2]) {
  Based b = base_at(o, d, c);
  Vld p = (o - c) + b.t0 * d; // closest approach, relative to the centre
  ld pl = len(p);
  int n = quadratic(dot(d, d), dot(p, d), (pl - r) * (pl + r), out);
  for (int i = 0; i < n; ++i) out[i] += b.t0;
  return n;
}

Hull sphere_hull(Vld c, ld r, Vld o, Vld d, ld u) {
  Hull h;
  ld rt[2];
  int n = sphere_roots(c, r, o, d, rt);
  for (int i = 0; i < n; ++i) h.add(rt[i], (o - c) + rt[i] * d, u);
  return h;
}

// G is jointly convex in (s, t); its minimiser over all t has t at the foot of the
// perpendicular from c(s), and if that foot lies beyond tmin or tmax the constrained
// minimiser lies on that bound (convexity), where it is a point-to-core problem of the
// same form.
std::pair<ld, ld> linear_core_gap(Vld a, ld ra, Vld b, ld rb, const PrimRay& ray) {
  Vld o = ray.o, d = ray.d, ab = b - a, w0 = a - o; // c(s) - o = w0 + s ab
  ld inv_dd = 1 / dot(d, d), k = ra - rb;          // -r(s) = -ra + s k
  ld w0d = dot(w0, d) * inv_dd, abd = dot(ab, d) * inv_dd;
  Vld u0 = w0 - w0d * d, u1 = ab - abd * d;
  ld s = argmin_norm_plus_linear(u0, u1, k);
  ld t = w0d + s * abd;
  if (t < ray.tmin || t > ray.tmax) {
    t = t < ray.tmin ? ray.tmin : ray.tmax;
    s = argmin_norm_plus_linear(w0 - t * d, ab, k);
  }
  return {len(w0 + s * ab - t * d) - (ra - s * k), t};
}

} // namespace detail

} // namespace masq::oracle
