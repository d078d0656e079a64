// Long-double capsule: the textbook cylinder quadratic plus two end spheres, solved with
// the ray re-based at its closest approach to the axis within the capsule's extent.
#include "oracle/prim_common.h"
#include "oracle/solve.h"

namespace masq::oracle {

using namespace detail;

namespace {

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

} // namespace

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

} // namespace masq::oracle
