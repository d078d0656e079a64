// The curve intersector's occlusion calls (MASQ_ANY_HIT: curve_intersect_mode with
// any = 1) against the long-double oracle, one ray and one curve at a time: they stop at
// the first certificate of a crossing (kernels/curve_occlusion.h: a point inside the
// solid at the window's start, a ray point inside it found at the curve point nearest
// the ray, or an entry not necessarily the nearest), so what is checked is
//  - hit or miss as the oracle's nearest crossing says, outside the fp32 band (the
//    closest-hit tests' rule, tests/curve_prims.h), on the ray families a witness could
//    get wrong: rays grazing the tube (1e-3..1e-1 r outside or inside it), rays through
//    the ball about the curve, rays nearly along it, and rays leaving or entering it
//    from its surface (shadow rays);
//  - the point the hit reports lies in the ray's window and in the solid (its distance
//    from the curve at most r, within the closest-hit tests' position tolerance).
#include "tests/curve_prims.h"
#include <gtest/gtest.h>
#include <algorithm>
#include <cmath>
#include <cstdio>

using namespace masq::test;

namespace {

KV::PrimHit run_occlusion(const Hair& h, glm::vec3 o, glm::vec3 d, float tmin = 0, float tmax = kInfF) {
  return KV::curve_intersect_mode(h.k, o, d, tmin, tmax, 1, g_curve_isect, 1);
}

// The distance from p to the curve's centre line: the nearest of 1024 samples, then a
// golden-section search on the interval about it (the distance is smooth and, that close,
// unimodal for these hair-like curves).
ld distance_to_curve(const Hair& h, const Vld& p) {
  const int n = 1024;
  int best = 0;
  ld bd = lenl(bez(h, 0) - p);
  for (int i = 1; i <= n; ++i) {
    ld di = lenl(bez(h, ld(i) / n) - p);
    if (di < bd) bd = di, best = i;
  }
  ld a = std::max<ld>(0, ld(best - 1) / n), b = std::min<ld>(1, ld(best + 1) / n);
  const ld g = (std::sqrt(5.0L) - 1) / 2;
  for (int k = 0; k < 60; ++k) {
    ld c = b - g * (b - a), e = a + g * (b - a);
    if (lenl(bez(h, c) - p) < lenl(bez(h, e) - p)) b = e;
    else a = c;
  }
  return std::min(bd, lenl(bez(h, (a + b) / 2) - p));
}

struct OcclusionTally {
  // Hit/miss against the oracle (compare's rule). Its t, normal and u tallies are not
  // read: an occlusion call's point need not be the nearest crossing.
  Tally hits;
  long outside = 0;   // hits whose point lies outside the window or the solid
  long n_hits = 0;
  void check(const Hair& h, const KV::PrimHit& k, const PrimRay& ray, const PrimResult& ref) {
    compare(k, ref, ray, h, hits);
    if (k.hit == 0) return;
    ++n_hits;
    const ld t = k.t;
    const ld tol = kTolRel * h.r + kBand * kU * (lenl(ray.o - h.centre) + h.len);
    const bool in_window = std::isfinite(k.t) && t >= ray.tmin && t <= ray.tmax;
    if (!in_window || distance_to_curve(h, ray.o + t * ray.d) > h.r + tol) ++outside;
  }
};

TEST_P(CurveIntersector, OcclusionCallsAgreeWithTheOracle) {
  Rng rng(0x0cc1);
  const ld r = 1e-4L;
  OcclusionTally grazing, through, along, surface;
  for (ld T : {0.0L, 1e5L})
    for (ld lr : {1e3L, 1e4L})
      for (int c = 0; c < 12; ++c) {
        Hair h = make_hair(rng, r, lr, T);
        for (int i = 0; i < 200; ++i) {
          // From afar: grazing the tube, or through the ball about a curve point.
          const ld dist = log_uni(rng, 1e1, 1e4) * h.r;
          SurfPt s = sample_surface(h, rng);
          ld delta = log_uni(rng, 1e-3, 1e-1) * (uni(rng, 0, 1) < 0.5 ? -1 : 1);
          Vld aim = s.p + (delta * h.r) * s.n, dir = rand_perp(rng, s.n);
          auto [og, dg] = aimed_ray(aim - dist * dir, aim, rng);
          PrimRay rg = ld_ray(og, dg);
          grazing.check(h, run_occlusion(h, og, dg), rg, masq::oracle::oracle_curve(h.prim, rg));

          aim = bez(h, uni(rng, 0, 1)) + (2 * h.r * std::cbrt(uni(rng, 0, 1))) * rand_unit(rng);
          dir = rand_unit(rng);
          auto [ot, dt] = aimed_ray(aim - dist * dir, aim, rng);
          PrimRay rt = ld_ray(ot, dt);
          through.check(h, run_occlusion(h, ot, dt), rt, masq::oracle::oracle_curve(h.prim, rt));

          // Nearly along the curve.
          ld sa = uni(rng, 0, 1);
          Vld tan = unitl(dbez(h, sa));
          ld theta = log_uni(rng, 1e-4, 0.2);
          dir = std::cos(theta) * tan + std::sin(theta) * rand_perp(rng, tan);
          aim = bez(h, sa) + (uni(rng, 0, 1.5) * h.r) * rand_perp(rng, tan);
          auto [oa, da] = aimed_ray(aim - log_uni(rng, 10 * h.r, 2 * h.len) * dir, aim, rng);
          PrimRay ra = ld_ray(oa, da);
          along.check(h, run_occlusion(h, oa, da), ra, masq::oracle::oracle_curve(h.prim, ra));

          // Shadow rays: from the surface, outward or back through the strand, to a
          // light at a finite distance or none.
          SurfPt f = sample_surface(h, rng);
          Vld side = rand_perp(rng, f.n);
          ld sign = uni(rng, 0, 1) < 0.5 ? 1 : -1;
          glm::vec3 of = to_f(f.p), df = to_f(unitl(sign * f.n + uni(rng, 0, 3) * side));
          float tmax = uni(rng, 0, 1) < 0.5 ? kInfF : float(log_uni(rng, 1e-1, 1e2) * h.r);
          PrimRay rs = ld_ray(of, df, 0, tmax);
          surface.check(h, run_occlusion(h, of, df, 0, tmax), rs, masq::oracle::oracle_curve(h.prim, rs));
        }
      }
  struct Family {
    const char* name;
    const OcclusionTally* t;
  } families[] = {{"grazing the tube", &grazing}, {"through the ball", &through}, {"nearly along", &along},
                  {"from the surface", &surface}};
  for (const Family& fam : families) {
    const OcclusionTally& t = *fam.t;
    std::printf("occlusion, %s: %ld rays (%.1f%% in the band), %ld hits, %ld flips outside the band (%ld raw), %ld hit "
                "points outside the window or the solid\n",
                fam.name, t.hits.n, 100 * t.hits.amb_rate(), t.n_hits, t.hits.flips, t.hits.flips_raw, t.outside);
    EXPECT_LT(t.hits.rate(), 1e-4) << fam.name << ": hit/miss disagreements outside the band";
    EXPECT_EQ(t.outside, 0) << fam.name;
    EXPECT_GT(t.n_hits, t.hits.n / 10) << fam.name << ": the family must hit";
  }
}

} // namespace

MASQ_CURVE_ISECT_SUITE;
