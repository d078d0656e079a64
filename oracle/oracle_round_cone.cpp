// Long-double round cone: the tangent cone of the two spheres plus their outer caps,
// solved with the ray re-based at its closest approach to the axis within the cone's
// extent.
#include "oracle/prim_common.h"
#include "oracle/solve.h"

namespace masq::oracle {

using namespace detail;

namespace {

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

} // namespace

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

} // namespace masq::oracle
