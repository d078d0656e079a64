// Long-double reference intersections, one primitive at a time. Written from the
// geometry, not from any fast-path formula in kernels/:
//  - sphere: the textbook quadratic; capsule: the textbook cylinder quadratic plus two
//    end spheres; round cone: the tangent cone of the two spheres plus their outer caps;
//    curve: the swept-sphere union solved over the curve parameter; triangle:
//    Moller-Trumbore.
//  - Every quadratic is solved with the ray re-based near the primitive (spheres: the
//    closest approach to the centre; capsule and cone: to the axis, within the solid's
//    axial extent), so its terms live on the primitive's scale rather than the distance
//    travelled or the length, and with the cancellation-free root pair.
//  - Clearance of spheres, capsules and cones is the exact gap between the ray segment
//    and the solid (closed form, see linear_core_gap); curves: see oracle_curve.
//  - Convex solids (sphere, capsule, cone): the ray meets the boundary at its entry and
//    exit, so the crossing interval is [min, max] of the boundary crossings found
//    (pieces meet at seams; a seam tolerance of 1e-12 of the size keeps both pieces'
//    crossings there, which deviate from the true surface only to second order).
#include "oracle/oracle_prims.h"
#include <algorithm>
#include <cmath>
#include <utility>

namespace masq::oracle {

namespace {

const ld kInf = std::numeric_limits<ld>::infinity();
constexpr ld kSeam = 1e-12L;

Vld operator+(Vld a, Vld b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
Vld operator-(Vld a, Vld b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
Vld operator*(ld s, Vld a) { return {s * a.x, s * a.y, s * a.z}; }
ld dot(Vld a, Vld b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
Vld cross(Vld a, Vld b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
ld len(Vld a) { return std::sqrt(dot(a, a)); }
Vld unit(Vld a) {
  ld l = len(a);
  return l > 0 ? (1 / l) * a : Vld{};
}
Vld from(const glm::vec3& v) { return {v.x, v.y, v.z}; }
bool finite(Vld a) { return std::isfinite(a.x) && std::isfinite(a.y) && std::isfinite(a.z); }
ld nonneg(float r) { return r > 0 ? ld(r) : 0; } // negative and NaN radii: no surface
ld clamp01(ld x) { return std::clamp<ld>(x, 0, 1); }

bool valid(const PrimRay& r) {
  return finite(r.o) && finite(r.d) && dot(r.d, r.d) > 0 && !std::isnan(r.tmin) && !std::isnan(r.tmax) &&
         r.tmin <= r.tmax && r.tmin < kInf;
}

ld window_lo(const PrimRay& ray, ld r, Vld centre, ld span = 0) {
  return std::max(ray.tmin, self_window_t(r, ray.o - centre, dot(ray.d, ray.d), span));
}

// A boundary crossing: ray parameter, outward normal (any length), axial/curve parameter.
struct Bound {
  ld t;
  Vld n;
  ld u;
};

// The first of the ascending crossings b[0..n) in [lo, tmax] is the hit.
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

// Crossings of a convex solid: the nearest and farthest are its entry and exit.
struct Hull {
  bool any = false;
  Bound in{kInf, {}, 0}, out{-kInf, {}, 0};
  void add(ld t, Vld n, ld u) {
    if (!std::isfinite(t)) return;
    any = true;
    if (t < in.t) in = {t, n, u};
    if (t > out.t) out = {t, n, u};
  }
};

void select_hull(const Hull& h, const PrimRay& ray, ld r, Vld centre, ld span, PrimResult& res) {
  if (!h.any) return;
  Bound b[2] = {h.in, h.out};
  select(b, 2, window_lo(ray, r, centre, span), ray.tmax, res);
}

// Real roots of A x^2 + 2 B x + C = 0 (any A), without cancellation between -B and the
// root of the discriminant.
int quadratic(ld A, ld B, ld C, ld out[2]) {
  if (A == 0) {
    if (B == 0) return 0;
    out[0] = -C / (2 * B);
    return 1;
  }
  ld disc = B * B - A * C;
  if (disc < 0) return 0;
  ld q = -(B + std::copysign(std::sqrt(disc), B));
  if (q == 0) { // B = 0 and A C = 0, so C = 0
    out[0] = 0;
    return 1;
  }
  out[0] = q / A;
  out[1] = C / q;
  return 2;
}

// The ray re-based at its closest approach to c: point o + t0 d, parameter tau = t - t0.
struct Based {
  Vld o;
  ld t0;
};
Based base_at(Vld o, Vld d, Vld c) {
  ld t0 = dot(c - o, d) / dot(d, d);
  return {o + t0 * d, t0};
}

// For a solid of revolution about the axis a + y w (|w| = 1) spanning y in [ylo, yhi]:
// the ray re-based at its closest approach to the axis line, kept inside that slab.
// Based at the centre alone, a ray meeting a long thin solid near one end would solve a
// quadratic whose terms are (L / r)^2 larger than their difference.
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

// Ray parameters where o + t d crosses the sphere (c, r).
int sphere_roots(Vld c, ld r, Vld o, Vld d, ld out[2]) {
  Based b = base_at(o, d, c);
  Vld p = (o - c) + b.t0 * d; // closest approach, relative to the centre
  ld pl = len(p);
  int n = quadratic(dot(d, d), dot(p, d), (pl - r) * (pl + r), out);
  for (int i = 0; i < n; ++i) out[i] += b.t0;
  return n;
}

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

// Clearance of a solid that is the union over s in [0,1] of the balls
// (a + s (b - a), ra + s (rb - ra)) (spheres, capsules, round cones):
//   G = min over s in [0,1], t in [tmin, tmax] of |o + t d - c(s)| - r(s),
// exactly the distance from the ray segment to the solid when the ray misses it
// (negative, a penetration depth, when it enters it). G is jointly convex in (s, t);
// its minimiser over all t has t at the foot of the perpendicular from c(s), and if that
// foot lies beyond tmin or tmax the constrained minimiser lies on that bound (convexity),
// where it is a point-to-core problem of the same form. Returns {G, t at the minimiser}.
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

// Minimum of a unimodal function over [lo, hi] by golden section: (argmin, min).
template <class Fn>
std::pair<ld, ld> golden_min(Fn fn, ld lo, ld hi, ld rel_width) {
  const ld g = 0.6180339887498948482045868343656381L;
  ld w0 = hi - lo;
  ld x1 = hi - g * (hi - lo), x2 = lo + g * (hi - lo), f1 = fn(x1), f2 = fn(x2);
  for (int it = 0; it < 200 && hi - lo > rel_width * w0; ++it) {
    if (f1 <= f2) {
      hi = x2;
      x2 = x1;
      f2 = f1;
      x1 = hi - g * (hi - lo);
      f1 = fn(x1);
    } else {
      lo = x1;
      x1 = x2;
      f1 = f2;
      x2 = lo + g * (hi - lo);
      f2 = fn(x2);
    }
  }
  return f1 <= f2 ? std::pair{x1, f1} : std::pair{x2, f2};
}

Hull sphere_hull(Vld c, ld r, Vld o, Vld d, ld u) {
  Hull h;
  ld rt[2];
  int n = sphere_roots(c, r, o, d, rt);
  for (int i = 0; i < n; ++i) h.add(rt[i], (o - c) + rt[i] * d, u);
  return h;
}

// Textbook capsule: the cylinder |(x - a) x (b - a)| = r |b - a| between the end planes,
// and the end spheres beyond them.
Hull capsule_hull(Vld a, Vld b, ld r, const PrimRay& ray) {
  Hull h;
  Vld d = ray.d;
  Vld ba = b - a;
  ld baba = dot(ba, ba), L = std::sqrt(baba);
  Based base = baba > 0 ? base_at_axis(ray.o, d, a, (1 / L) * ba, -r, L + r) : base_at(ray.o, d, a);
  Vld oa = base.o - a;
  ld bard = dot(ba, d), baoa = dot(ba, oa);
  ld tol = kSeam * (L + r) * L; // in units of y = ba . x
  ld rt[2];
  if (baba > 0) {
    Vld oxb = cross(oa, ba), dxb = cross(d, ba);
    ld m = len(oxb);
    int n = quadratic(dot(dxb, dxb), dot(oxb, dxb), (m - r * L) * (m + r * L), rt);
    for (int i = 0; i < n; ++i) {
      ld y = baoa + rt[i] * bard;
      if (y >= -tol && y <= baba + tol) h.add(base.t0 + rt[i], oa + rt[i] * d - (y / baba) * ba, clamp01(y / baba));
    }
  }
  for (int e = 0; e < 2; ++e) {
    Vld c = e == 0 ? a : b;
    int n = sphere_roots(c, r, base.o, d, rt);
    for (int i = 0; i < n; ++i) {
      ld y = baoa + rt[i] * bard;
      if (baba == 0 || (e == 0 ? y <= tol : y >= baba - tol)) h.add(base.t0 + rt[i], (base.o - c) + rt[i] * d, ld(e));
    }
  }
  return h;
}

// Round cone = convex hull of the balls (a, ra), (b, rb). With axis w = (b - a) / L and
// sin(phi) = (ra - rb) / L, the tangent cone touches ball a in the plane y = ra sin(phi)
// and ball b in y = L + rb sin(phi) (y: axial coordinate from a); between them the
// surface is cos^2(phi) |x_perp|^2 = (ra - y sin(phi))^2; outside them the surface is the
// outer caps of the two spheres (the points whose outward normal n has n.w <= sin(phi),
// resp. >= sin(phi): the support points of the hull). When one ball contains the other
// (L <= |ra - rb|) the hull is the bigger ball.
Hull cone_hull(Vld a, ld ra, Vld b, ld rb, const PrimRay& ray) {
  Vld d = ray.d;
  Vld ab = b - a;
  ld L = len(ab), rmax = std::max(ra, rb), rmin = std::min(ra, rb);
  if (L + rmin <= rmax) return ra >= rb ? sphere_hull(a, ra, ray.o, d, 0) : sphere_hull(b, rb, ray.o, d, 1);
  Hull h;
  Vld w = (1 / L) * ab;
  Based base = base_at_axis(ray.o, d, a, w, -rmax, L + rmax);
  ld s = (ra - rb) / L, c2 = (1 - s) * (1 + s), c = std::sqrt(c2);
  Vld x0 = base.o - a;
  ld y0 = dot(x0, w), dw = dot(d, w);
  Vld x0p = x0 - y0 * w, dp = d - dw * w;
  ld e0 = ra - y0 * s, e1 = -dw * s, lx = len(x0p);
  ld ya = ra * s, yb = L + rb * s, tol = kSeam * (L + rmax);
  ld rt[2];
  int n = quadratic(c2 * dot(dp, dp) - e1 * e1, c2 * dot(x0p, dp) - e0 * e1, (c * lx - e0) * (c * lx + e0), rt);
  for (int i = 0; i < n; ++i) {
    ld y = y0 + rt[i] * dw;
    if (y >= ya - tol && y <= yb + tol) {
      Vld xp = x0p + rt[i] * dp;
      h.add(base.t0 + rt[i], c2 * xp + (s * (ra - y * s)) * w, clamp01(y / L));
    }
  }
  for (int e = 0; e < 2; ++e) {
    Vld cc = e == 0 ? a : b;
    int m = sphere_roots(cc, e == 0 ? ra : rb, base.o, d, rt);
    for (int i = 0; i < m; ++i) {
      ld y = y0 + rt[i] * dw;
      if (e == 0 ? y <= ya + tol : y >= yb - tol) h.add(base.t0 + rt[i], (base.o - cc) + rt[i] * d, clamp01(y / L));
    }
  }
  return h;
}

// ---- polynomials on [0, 1] (curves) ----

ld peval(const ld* p, int n, ld x) {
  ld v = p[n];
  for (int i = n - 1; i >= 0; --i) v = v * x + p[i];
  return v;
}

struct Roots {
  ld r[8];
  int n = 0;
  void push(ld x) {
    if (n < 8) r[n++] = x;
  }
};

// Root of fn in [a, b] where fn changes sign (fa: the value at a); fn(x) returns
// {value, derivative}. Newton steps, replaced by bisection whenever they leave the
// bracket, until the step or the bracket reaches long-double resolution.
template <class Fn>
ld solve_bracketed(Fn fn, ld a, ld b, ld fa) {
  ld x = 0.5L * (a + b);
  for (int it = 0; it < 160; ++it) {
    auto [fx, dfx] = fn(x);
    if (fx == 0) return x;
    if ((fx < 0) == (fa < 0)) {
      a = x;
      fa = fx;
    } else {
      b = x;
    }
    ld xn = x - fx / dfx;
    if (!(xn > a && xn < b) || it % 8 == 7) xn = 0.5L * (a + b); // periodic bisection bounds the count
    if (xn <= a || xn >= b) return x;
    if (std::fabs(xn - x) <= 4 * std::numeric_limits<ld>::epsilon() * std::fabs(x)) return xn;
    x = xn;
  }
  return x;
}

// Every root of the degree-n polynomial p in (lo, hi), ascending: the derivative's roots
// split [lo, hi] into pieces on which p is monotone, so each sign change is one root.
Roots poly_roots(const ld* p, int n, ld lo, ld hi) {
  Roots out;
  while (n > 0 && p[n] == 0) --n;
  if (n <= 0) return out;
  if (n == 1) {
    ld x = -p[0] / p[1];
    if (x > lo && x < hi) out.push(x);
    return out;
  }
  ld dp[8];
  for (int i = 0; i < n; ++i) dp[i] = ld(i + 1) * p[i + 1];
  Roots cr = poly_roots(dp, n - 1, lo, hi);
  ld nodes[10];
  int nn = 0;
  nodes[nn++] = lo;
  for (int i = 0; i < cr.n; ++i) nodes[nn++] = cr.r[i];
  nodes[nn++] = hi;
  ld v0 = peval(p, n, lo);
  for (int k = 0; k + 1 < nn; ++k) {
    ld v1 = peval(p, n, nodes[k + 1]);
    if (v0 == 0 && k > 0) {
      out.push(nodes[k]);
    } else if ((v0 < 0 && v1 > 0) || (v0 > 0 && v1 < 0)) {
      auto fn = [&](ld x) { return std::pair{peval(p, n, x), peval(dp, n - 1, x)}; };
      out.push(solve_bracketed(fn, nodes[k], nodes[k + 1], v0));
    }
    v0 = v1;
  }
  return out;
}

// A cubic Bezier in power basis (vector coefficients c0 + c1 s + c2 s^2 + c3 s^3).
struct Cubic {
  Vld c[4];
  Vld at(ld s) const { return c[0] + s * (c[1] + s * (c[2] + s * c[3])); }
  Vld tangent(ld s) const { return c[1] + s * (2 * c[2] + (3 * s) * c[3]); }
  // Coefficients of at(s) . tangent(s) (degree 5): its roots are where |at(s)| is stationary.
  void stationary_poly(ld g[6]) const {
    for (int k = 0; k < 6; ++k) g[k] = 0;
    for (int i = 0; i < 4; ++i)
      for (int j = 1; j < 4; ++j) g[i + j - 1] += ld(j) * dot(c[i], c[j]);
  }
};
template <class T>
void power_basis(const T p[4], T c[4]) {
  c[0] = p[0];
  c[1] = 3 * (p[1] - p[0]);
  c[2] = 3 * (p[0] - 2 * p[1] + p[2]);
  c[3] = p[3] - p[0] + 3 * (p[1] - p[2]);
}

// Nodes 0, stationary points of |q(s)|, 1: |q| is monotone between consecutive nodes.
int stationary_nodes(const Cubic& q, ld nodes[8]) {
  ld g[6];
  q.stationary_poly(g);
  Roots cr = poly_roots(g, 5, 0, 1);
  int n = 0;
  nodes[n++] = 0;
  for (int i = 0; i < cr.n; ++i) nodes[n++] = cr.r[i];
  nodes[n++] = 1;
  return n;
}

struct SInterval {
  ld t_in, s_in, t_out, s_out;
};

} // namespace

ld self_window_t(ld radius, Vld o_minus_centre, ld dd, ld span) {
  const ld rel = 1.0L / 1024, u = 1.0L / 16777216;
  return (rel * std::max<ld>(radius, 0) + 32 * u * (len(o_minus_centre) + span)) / std::sqrt(dd);
}

// Clearance first: it is the exact gap between the ray segment and the solid, so a
// clearly positive gap means no crossing in [tmin, tmax] and the crossing solve is
// skipped (most primitive/ray pairs of a brute-force scene trace).
bool gap_clear(ld gap, ld r) { return gap > 1e-8L * r; }

PrimResult oracle_sphere(const SpherePrim& p, const PrimRay& ray) {
  PrimResult res;
  ld r = nonneg(p.radius);
  if (!valid(ray) || r == 0) return res;
  Vld c = from(p.center);
  auto [gap, t] = linear_core_gap(c, r, c, r, ray);
  res.clearance = std::fabs(gap) / r;
  res.t_near = t;
  if (!gap_clear(gap, r)) select_hull(sphere_hull(c, r, ray.o, ray.d, 0), ray, r, c, 0, res);
  return res;
}

PrimResult oracle_capsule(const CapsulePrim& p, const PrimRay& ray) {
  PrimResult res;
  ld r = nonneg(p.radius);
  if (!valid(ray) || r == 0) return res;
  Vld a = from(p.a), b = from(p.b);
  auto [gap, t] = linear_core_gap(a, r, b, r, ray);
  res.clearance = std::fabs(gap) / r;
  res.t_near = t;
  if (!gap_clear(gap, r)) select_hull(capsule_hull(a, b, r, ray), ray, r, 0.5L * (a + b), len(b - a), res);
  return res;
}

// Clearance relative to max(ra, rb).
PrimResult oracle_round_cone(const RoundConePrim& p, const PrimRay& ray) {
  PrimResult res;
  ld ra = nonneg(p.ra), rb = nonneg(p.rb), rmax = std::max(ra, rb);
  if (!valid(ray) || rmax == 0) return res;
  Vld a = from(p.a), b = from(p.b);
  auto [gap, t] = linear_core_gap(a, ra, b, rb, ray);
  res.clearance = std::fabs(gap) / rmax;
  res.t_near = t;
  if (!gap_clear(gap, rmax)) select_hull(cone_hull(a, ra, b, rb, ray), ray, rmax, 0.5L * (a + b), len(b - a), res);
  return res;
}

// Swept sphere: the solid is the union over s in [0,1] of the balls B(C(s), r). In the
// ray's frame C(s) - o = W(s) + T(s) d with W perpendicular to d, so the ball at s meets
// the ray line where f(s) = |W(s)|^2 - r^2 <= 0, in [T(s) - h(s), T(s) + h(s)],
// h = sqrt(-f) / |d|. f has degree 6: its stationary points (roots of W . W', degree 5)
// are found exactly, f is monotone between them, so every s-interval where f <= 0 is
// found with its ends to long-double precision, however short (silhouette rays). Over
// one connected s-interval the union of the ray intervals is one interval
// [min t_in, max t_out]; those extremes are found by sampling (with the stationary
// points of f and T as extra samples) and golden-section refinement of each sampled
// local extremum. The t-intervals of all s-intervals are merged; the hit is the first
// boundary point in the window, and its normal points from C(s*) (s*: the extremiser).
PrimResult oracle_curve(const CurvePrim& p, const PrimRay& ray) {
  PrimResult res;
  ld r = nonneg(p.radius);
  if (!valid(ray) || r == 0) return res;
  if (p.p[0] == p.p[1] && p.p[0] == p.p[2] && p.p[0] == p.p[3]) return oracle_sphere({p.p[0], p.radius}, ray);
  Vld o = ray.o, d = ray.d;
  ld dd = dot(d, d), dl = std::sqrt(dd);
  Vld P[4], perp[4], centre;
  ld ax[4];
  for (int i = 0; i < 4; ++i) {
    P[i] = from(p.p[i]);
    centre = centre + 0.25L * P[i];
    Vld q = P[i] - o;
    ax[i] = dot(q, d) / dd;
    perp[i] = q - ax[i] * d;
  }
  Cubic W;
  power_basis(perp, W.c);
  ld T[4];
  power_basis(ax, T);
  auto Tat = [&](ld s) { return peval(T, 3, s); };
  auto f = [&](ld s) {
    ld m = len(W.at(s));
    return (m - r) * (m + r);
  };

  // s-intervals where the ray line is within r of C(s).
  ld nodes[8];
  int nn = stationary_nodes(W, nodes);
  ld fv[8] = {};
  for (int k = 0; k < nn; ++k) fv[k] = f(nodes[k]);
  auto f_df = [&](ld s) { return std::pair{f(s), 2 * dot(W.at(s), W.tangent(s))}; };
  std::pair<ld, ld> sint[8];
  int ns = 0;
  bool inside = fv[0] <= 0;
  ld start = 0;
  for (int k = 1; k < nn; ++k) {
    bool in_k = fv[k] <= 0;
    if (in_k == inside) continue;
    ld root = solve_bracketed(f_df, nodes[k - 1], nodes[k], fv[k - 1]);
    if (inside) sint[ns++] = {start, root};
    else start = root;
    inside = in_k;
  }
  if (inside) sint[ns++] = {start, 1};

  // Extremes of t_in(s) = T(s) - h(s) and t_out(s) = T(s) + h(s) over each s-interval.
  ld tcrit_poly[3] = {T[1], 2 * T[2], 3 * T[3]};
  Roots tcrit = poly_roots(tcrit_poly, 2, 0, 1);
  // Minimum of psi(s) = sign T(s) - h(s) over [s0, s1]: sign = +1 gives min t_in,
  // sign = -1 gives -max t_out. Returns (argmin, sign * min) = (s*, t_in or t_out).
  auto extreme = [&](ld s0, ld s1, ld sign) {
    auto psi = [&](ld s) { return sign * Tat(s) - std::sqrt(std::max<ld>(0, -f(s))) / dl; };
    constexpr int kSamples = 16, kMax = kSamples + 1 + 16;
    ld xs[kMax], val[kMax];
    int m = 0;
    for (int i = 0; i < kSamples; ++i) xs[m++] = s0 + (s1 - s0) * ld(i) / kSamples;
    xs[m++] = s1;
    for (int k = 0; k < nn; ++k)
      if (nodes[k] > s0 && nodes[k] < s1) xs[m++] = nodes[k];
    for (int k = 0; k < tcrit.n; ++k)
      if (tcrit.r[k] > s0 && tcrit.r[k] < s1) xs[m++] = tcrit.r[k];
    std::sort(xs, xs + m);
    int kept = 1; // drop samples that (nearly) coincide: a refinement bracket needs width
    for (int i = 1; i < m; ++i)
      if (xs[i] - xs[kept - 1] > 1e-12L * (s1 - s0)) xs[kept++] = xs[i];
    xs[kept - 1] = s1;
    m = kept;
    ld best_s = xs[0], best_v = kInf;
    for (int i = 0; i < m; ++i) {
      val[i] = psi(xs[i]);
      if (val[i] < best_v) {
        best_v = val[i];
        best_s = xs[i];
      }
    }
    // Refine around each sampled local minimum (a run of equal values counts as one);
    // the sampled ends keep their exact values.
    int refined = 0;
    for (int i = 0; i < m && refined < 4; ++i) {
      int j = i;
      while (j + 1 < m && val[j + 1] == val[i]) ++j;
      bool local = (i == 0 || val[i] < val[i - 1]) && (j + 1 == m || val[j] < val[j + 1]);
      ld lo = xs[std::max(i - 1, 0)], hi = xs[std::min(j + 1, m - 1)];
      i = j;
      if (!local || !(hi > lo)) continue;
      ++refined;
      auto [x, v] = golden_min(psi, lo, hi, 1e-13L);
      if (v < best_v) {
        best_v = v;
        best_s = x;
      }
    }
    return std::pair{best_s, sign * best_v};
  };
  SInterval iv[8];
  for (int i = 0; i < ns; ++i) {
    auto [si, ti] = extreme(sint[i].first, sint[i].second, 1);
    auto [so, to] = extreme(sint[i].first, sint[i].second, -1);
    iv[i] = {ti, si, to, so};
  }
  std::sort(iv, iv + ns, [](const SInterval& x, const SInterval& y) { return x.t_in < y.t_in; });
  Bound bounds[16];
  int nb = 0;
  auto normal_at = [&](ld t, ld s) { return (t - Tat(s)) * d - W.at(s); };
  for (int i = 0; i < ns;) {
    SInterval cur = iv[i++];
    while (i < ns && iv[i].t_in <= cur.t_out) {
      if (iv[i].t_out > cur.t_out) {
        cur.t_out = iv[i].t_out;
        cur.s_out = iv[i].s_out;
      }
      ++i;
    }
    bounds[nb++] = {cur.t_in, normal_at(cur.t_in, cur.s_in), cur.s_in};
    bounds[nb++] = {cur.t_out, normal_at(cur.t_out, cur.s_out), cur.s_out};
  }
  select(bounds, nb, window_lo(ray, r, centre, len(P[1] - P[0]) + len(P[2] - P[1]) + len(P[3] - P[2])), ray.tmax, res);

  // Clearance: min over s of distance(C(s), ray segment). Where the nearest segment point
  // is interior it is |W(s)| at a stationary point (or an end) with T(s) in [tmin, tmax];
  // otherwise it is the distance from a segment end to the curve.
  ld best = kInf, best_t = kInf;
  for (int k = 0; k < nn; ++k) {
    ld tc = Tat(nodes[k]);
    ld dist = len(W.at(nodes[k]));
    if (tc >= ray.tmin && tc <= ray.tmax && dist < best) {
      best = dist;
      best_t = tc;
    }
  }
  ld hull_radius = 0; // the curve lies in the control points' hull, so in this ball about centre
  for (const Vld& q : P) hull_radius = std::max(hull_radius, len(q - centre));
  for (ld te : {ray.tmin, ray.tmax}) {
    if (!std::isfinite(te) || len((o + te * d) - centre) - hull_radius >= best) continue;
    Cubic V = W; // C(s) - (o + te d) = W(s) + (T(s) - te) d
    for (int i = 0; i < 4; ++i) V.c[i] = V.c[i] + (T[i] - (i == 0 ? te : 0)) * d;
    ld vn[8];
    int vnn = stationary_nodes(V, vn);
    for (int k = 0; k < vnn; ++k) {
      ld dist = len(V.at(vn[k]));
      if (dist < best) {
        best = dist;
        best_t = te;
      }
    }
  }
  res.clearance = std::fabs(best - r) / r;
  res.t_near = best_t;
  return res;
}

PrimResult oracle_triangle(const glm::vec3& v0, const glm::vec3& v1, const glm::vec3& v2, const PrimRay& ray) {
  PrimResult res;
  if (!valid(ray)) return res;
  Vld p0 = from(v0), p1 = from(v1), p2 = from(v2), o = ray.o, d = ray.d;
  Vld e1 = p1 - p0, e2 = p2 - p0;
  // A triangle without area (coincident or collinear vertices) has no surface. The
  // cross product of fp32 differences is exact in long double, so this test is exact.
  Vld area = cross(e1, e2);
  if (area.x == 0 && area.y == 0 && area.z == 0) return res;
  Vld pv = cross(d, e2);
  ld det = dot(e1, pv);
  if (det == 0) return res;
  Vld tv = o - p0;
  ld u = dot(tv, pv) / det;
  Vld qv = cross(tv, e1);
  ld v = dot(d, qv) / det;
  ld t = dot(e2, qv) / det;
  ld w = 1 - u - v;
  if (!(t >= ray.tmin && t <= ray.tmax)) return res;
  // Clearance: the smallest barycentric, times the sine of the angle between ray and
  // plane. Seen along the ray, the triangle is a sliver that thin, so this is the
  // ray's distance to the nearest edge perpendicular to the ray, relative to the
  // triangle's size: what fp32 rounding of the ray's position competes with.
  const ld sin_angle = std::fabs(dot(d, area)) / (len(d) * len(area));
  res.clearance = std::min({std::fabs(u), std::fabs(v), std::fabs(w)}) * sin_angle;
  res.t_near = t;
  // The kernels' plane rule: an origin on the triangle's plane (within 16u of
  // |o - v0| + |v0|) never hits the triangle.
  const ld plane_tol = 16.0L / 16777216.0L * (len(tv) + len(p0)) * len(area);
  if (std::fabs(dot(tv, area)) <= plane_tol) return res;
  if (u >= 0 && v >= 0 && w >= 0 && t >= self_window_t(0, tv, dot(d, d))) {
    res.hit = true;
    res.t = t;
    res.normal = unit(cross(e1, e2));
    res.u = u;
    res.v = v;
  }
  return res;
}

} // namespace masq::oracle
