// Long-double triangle: Moller-Trumbore, with the kernels' plane rule and the self
// window of the oracle_prims.h contract.
#include "oracle/prim_common.h"

namespace masq::oracle {

using namespace detail;

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
