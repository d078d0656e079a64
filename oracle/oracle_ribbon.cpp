// Long-double ribbon (oracle_prims.h's contract; the flat strip of scenes/scene.h's
// RibbonPrim). Written from the definition, not from the kernel's frame: the crossing
// solves o + t d = p0 + s a + v w_hat (a = p1 - p0, w_hat the unit width direction)
// for (s, v, t) by Cramer's rule, and keeps it when s is in [0, 1] and |v| <= r(s).
// A flat primitive has no inside: like the triangle it follows the kernels' plane rule
// and the self window with r = 0 (span |a|).
#include "oracle/prim_common.h"

namespace masq::oracle {

using namespace detail;

namespace {
ld det3(Vld a, Vld b, Vld c) { return dot(a, cross(b, c)); }
} // namespace

PrimResult oracle_ribbon(const RibbonPrim& p, const PrimRay& ray) {
  PrimResult res;
  if (!valid(ray)) return res;
  const Vld p0 = from(p.p0), a = from(p.p1) - p0, n = from(p.n), o = ray.o, d = ray.d;
  const ld r0 = nonneg(p.r0), r1 = nonneg(p.r1), rmax = std::max(r0, r1);
  const ld la = len(a);
  if (!(la > 0) || !(rmax > 0)) return res;
  // The width direction exists when the normal is more than 2^-12 rad off the axis
  // (sin^2 > 2^-24, the kernels' bound): closer, fp32 cannot say which way it points.
  const Vld w = cross(n, a);
  const ld sin2 = dot(w, w) / (dot(n, n) * la * la);
  if (!(sin2 > 1.0L / 16777216.0L)) return res;
  const Vld wh = unit(w), nd = {-d.x, -d.y, -d.z}, rhs = o - p0;
  const ld det = det3(a, wh, nd);
  if (det == 0) return res; // the ray runs in the ribbon's plane
  const ld s = det3(rhs, wh, nd) / det, v = det3(a, rhs, nd) / det, t = det3(a, wh, rhs) / det;
  if (!(t >= ray.tmin && t <= ray.tmax)) return res;
  const ld r = std::max<ld>(r0 + s * (r1 - r0), 0);
  // Clearance: the crossing's distance to the nearest edge of the strip (the long edges
  // lean by atan((r1 - r0) / |a|)), relative to rmax, times the sine of the angle
  // between ray and plane (as seen along the ray, the strip is that much thinner).
  const Vld nrm = unit(cross(a, wh));
  const ld lean = 1 / std::sqrt(1 + (r1 - r0) * (r1 - r0) / (la * la));
  const ld edge = std::min({std::fabs(r - std::fabs(v)) * lean, std::fabs(s) * la, std::fabs(1 - s) * la});
  res.clearance = edge / rmax * std::fabs(dot(d, nrm)) / len(d);
  res.t_near = t;
  const Vld c = p0 + 0.5L * a, oc = o - c;
  const ld plane_tol = 16.0L / 16777216.0L * (len(oc) + len(p0) + la);
  if (std::fabs(dot(oc, nrm)) <= plane_tol) return res;
  if (s >= 0 && s <= 1 && std::fabs(v) <= r && t >= window_lo(ray, 0, c, la)) {
    res.hit = true;
    res.t = t;
    res.normal = nrm;
    res.u = s;
    res.v = r > 0 ? v / r : 0;
  }
  return res;
}

} // namespace masq::oracle
