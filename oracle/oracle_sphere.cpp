// Long-double sphere: the textbook quadratic, solved with the ray re-based at its
// closest approach to the centre (prim_common.h's sphere_roots).
#include "oracle/prim_common.h"

namespace masq::oracle {

using namespace detail;

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

} // namespace masq::oracle
