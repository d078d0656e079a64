// Long-double cubic curve: the union of the balls of radius r swept along a cubic
// Bezier, solved over the curve parameter (the s-intervals where the ray line is within
// r of the curve found exactly, the ray interval of each by sampling and refinement).
#include "oracle/prim_common.h"
#include "oracle/solve.h"

namespace masq::oracle {

using namespace detail;

namespace {

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

} // namespace masq::oracle
