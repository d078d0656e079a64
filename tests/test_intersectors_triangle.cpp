// The triangle intersectors (kernels/intersect_triangle.h, compiled as C++) against the
// independent long-double oracle (oracle/oracle_prims.h), one ray and one triangle at a
// time: the robust variant asserted, Moller-Trumbore as written measured and printed.
// The band of legitimate fp32 disagreement: tests/intersector_compare.h (here r is the
// triangle's smallest height times the cosine of the incidence angle).
#include "kernels/intersect_triangle.h"
#include "tests/intersector_compare.h"
#include <gtest/gtest.h>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

using namespace masq::test;

namespace {

namespace K = masq::kernel;

const ld kInfL = std::numeric_limits<ld>::infinity();

struct Tri {
  glm::vec3 v0, v1, v2;
};
K::Triangle ktri(const Tri& t) {
  return {{t.v0.x, t.v0.y, t.v0.z}, {t.v1.x, t.v1.y, t.v1.z}, {t.v2.x, t.v2.y, t.v2.z}, {0, 0, 0}};
}

TEST(Intersectors, TrianglesMatchOracle) {
  Rng rng(0x7a1);
  std::printf("triangles: size S, origin distance D, translation T\n");
  Tally robust_all, fast_all;
  StartTally surface_steep, surface_any;
  long fast_self = 0, fast_rays = 0;
  for (ld T : {0.0L, 1e5L})
    for (ld S : {1e-3L, 1.0L})
      for (ld dist_s : {1.0L, 1e2L, 1e4L}) {
        if (T > 0 && S < 1) continue; // the 1e5 grid (2^-7) would collapse the triangle
        Tally robust, fast;
        for (int k = 0; k < 20; ++k) {
          Vld base = Vld{uni(rng, -1, 1), uni(rng, -1, 1), uni(rng, -1, 1)} + Vld{T, T, T};
          Tri tr{to_f(base), to_f(base + S * rand_unit(rng)), to_f(base + S * rand_unit(rng))};
          Vld p0 = to_ld(tr.v0), p1 = to_ld(tr.v1), p2 = to_ld(tr.v2);
          Vld nrm = crossl(p1 - p0, p2 - p0);
          ld emax = std::max({lenl(p1 - p0), lenl(p2 - p1), lenl(p0 - p2)});
          ld hmin = lenl(nrm) / emax; // smallest height
          if (!(hmin > 1e-2L * S)) continue;
          Scale sc{p0, emax, hmin, kInfL, hmin};
          for (int i = 0; i < 150; ++i) {
            // Aim at barycentrics in [-0.2, 1.2], half of them within 1e-3..1e-1 of an edge.
            ld bu = uni(rng, -0.2, 1.2), bv = uni(rng, -0.2, 1.2);
            if (i % 2 == 0) {
              ld e = log_uni(rng, 1e-3, 1e-1) * (uni(rng, 0, 1) < 0.5 ? -1 : 1);
              bu = uni(rng, 0, 1);
              bv = i % 4 == 0 ? e : 1 - bu - e;
            }
            Vld aim = p0 + bu * (p1 - p0) + bv * (p2 - p0);
            Vld o = aim + (dist_s * S) * rand_unit(rng);
            auto [of, df] = aimed_ray(o, aim, rng);
            PrimRay ray = ld_ray(of, df);
            PrimResult ref = masq::oracle::oracle_triangle(tr.v0, tr.v1, tr.v2, ray);
            // A lateral error e moves the plane crossing by e / cos(i) in the plane:
            // the barycentric band is relative to hmin cos(i).
            Scale sci = sc;
            sci.r = hmin * std::max<ld>(std::fabs(dotl(unitl(nrm), ray.d)) / lenl(ray.d), 1e-6L);
            compare(KV::intersect_triangle(ktri(tr), of, df, 0, kInfF), ref, ray, sci, robust);
            compare(KV::intersect_triangle_fast(ktri(tr), of, df, 0, kInfF), ref, ray, sci, fast);
          }
          // Rays leaving a point of the triangle must not hit it again. Only where fp32
          // can place a point on the triangle within the window (8 u |o - v0|): near the
          // world origin and not much smaller than its distance from it.
          for (int i = 0; i < (T == 0 && S == 1 ? 50 : 0); ++i) {
            ld bu = uni(rng, 0.05, 0.9), bv = uni(rng, 0.05, 0.95 - bu);
            Vld pt = p0 + bu * (p1 - p0) + bv * (p2 - p0);
            glm::vec3 of = to_f(pt);
            Vld un = unitl(nrm);
            Vld dir = rand_unit(rng);
            bool steep = i % 2 == 0; // half of them at least 60 degrees from the plane
            if (steep) dir = unitl((dotl(dir, un) < 0 ? -1.0L : 1.0L) * un + uni(rng, 0, 0.55) * rand_perp(rng, un));
            glm::vec3 df = to_f(log_uni(rng, 1e-2, 1e2) * dir);
            Vld dl = to_ld(df);
            ld dn = dotl(dl, un);
            ld tcross = -dotl(to_ld(of) - pt, un) / dn;
            ld tself = masq::oracle::self_window_t(0, to_ld(of) - p0, dotl(dl, dl));
            PrimRay ray = ld_ray(of, df);
            (steep ? surface_steep : surface_any)
                .add(tcross, tself, 0, KV::intersect_triangle(ktri(tr), of, df, 0, kInfF).hit,
                     masq::oracle::oracle_triangle(tr.v0, tr.v1, tr.v2, ray).hit);
            ++fast_rays;
            fast_self += KV::intersect_triangle_fast(ktri(tr), of, df, 0, kInfF).hit;
          }
        }
        std::printf("  T %6.0Lg S %5.0Lg D/S %5.0Lg | %5ld rays, band %5.1f%% | robust %.1e (raw %.1e) | fast raw %.2f%% "
                    "(outside band %.2f%%)\n",
                    T, S, dist_s, robust.n, 100 * robust.amb_rate(), robust.rate(), robust.rate_raw(),
                    100 * fast.rate_raw(), 100 * fast.rate());
        robust_all.add(robust);
        fast_all.add(fast);
      }
  expect_robust(robust_all, "triangles");
  std::printf("Moller-Trumbore: %.3f%% raw, %.2e outside the band\n", 100 * fast_all.rate_raw(), fast_all.rate());
  // The triangle window (8 u |o - v0| / |d|) has no size term, while t from any fp32
  // formula errs by ~ u max|o - v_i| / cos(incidence): rays leaving at a grazing angle
  // can still see their own triangle. Held to zero only for steep rays; printed for all.
  surface_steep.check("triangles, rays from the surface, >= 60 deg from the plane");
  surface_any.report("triangles, rays from the surface, any direction");
  EXPECT_LT(double(surface_any.held_hits), 0.01 * double(surface_any.held));
  std::printf("Moller-Trumbore (no window): self hits on %.1f%% of %ld surface rays\n",
              100.0 * double(fast_self) / double(fast_rays), fast_rays);
}


// The self-intersection window on its own: origins just off a triangle's plane (where
// its plane rule lets the ray through), rays straight at it, crossings a little inside
// and a little beyond t_self (the oracle's self_window_t). The robust test must drop the
// first and keep the second. TrianglesMatchOracle's surface rays cannot tell: their
// origins lie within the plane rule's reach, so it passes with the window removed (this
// test then fails on all 2,000 crossings inside it).
TEST(Intersectors, TriangleSelfWindowHoldsOffThePlane) {
  Rng rng(0x5e1f);
  const ld u = ld(MASQ_U);
  int inside = 0, beyond = 0, inside_hits = 0, beyond_misses = 0;
  for (int i = 0; i < 4000; ++i) {
    ld R = log_uni(rng, 1e-1, 1e2); // |o - v0|
    Vld n = rand_unit(rng), t1 = rand_perp(rng, n);
    Vld t2 = crossl(n, t1);
    Vld v0 = (0.02L * R) * rand_unit(rng); // |v0| small beside |o - v0|: the plane test's bound stays below t_self
    Tri tr{to_f(v0), to_f(v0 + (4 * R) * t1), to_f(v0 + (4 * R) * t2)};
    Vld p0 = to_ld(tr.v0), p1 = to_ld(tr.v1), p2 = to_ld(tr.v2);
    Vld un = unitl(crossl(p1 - p0, p2 - p0));
    bool in = i % 2 == 0;
    Vld foot = p0 + R * (uni(rng, 0.3, 0.7) * unitl(p1 - p0) + uni(rng, 0.3, 0.7) * unitl(p2 - p0));
    Vld d = -log_uni(rng, 1e-2, 1e2) * un;
    glm::vec3 df = to_f(d);
    // Height over the plane as a fraction of the window's length along d (32 u |o - v0|).
    ld h = (in ? uni(rng, 0.62, 0.85) : uni(rng, 1.2, 2.0)) * 32 * u * lenl(foot - p0);
    glm::vec3 of = to_f(foot + h * un);
    Vld ol = to_ld(of), dl = to_ld(df);
    ld tcross = -dotl(ol - p0, un) / dotl(dl, un);
    ld tself = masq::oracle::self_window_t(0, ol - p0, dotl(dl, dl));
    ld plane_bound = 16 * u * (lenl(ol - p0) + lenl(p0)); // the plane test's, as a distance
    ld height = std::fabs(dotl(ol - p0, un));
    if (!(height > 1.05L * plane_bound)) continue; // the plane test decides these
    bool hit = KV::intersect_triangle(ktri(tr), of, df, 0, kInfF).hit != 0;
    if (tcross < 0.95L * tself) {
      ++inside;
      inside_hits += hit;
    } else if (tcross > 1.05L * tself) {
      ++beyond;
      beyond_misses += !hit;
    }
  }
  std::printf("self window off the plane: %d crossings inside it (%d hit), %d beyond it (%d missed)\n", inside,
              inside_hits, beyond, beyond_misses);
  ASSERT_GT(inside, 500);
  ASSERT_GT(beyond, 500);
  EXPECT_EQ(inside_hits, 0);
  EXPECT_EQ(beyond_misses, 0);
}

} // namespace
