// The ribbon intersectors (kernels/intersect_ribbon.h, compiled as C++) against the
// independent long-double oracle (oracle/oracle_ribbon.cpp), one ray and one ribbon at a
// time: the robust variant asserted, the textbook plane crossing measured and printed.
// The band of legitimate fp32 disagreement: tests/intersector_compare.h, with r the
// ribbon's largest half-width times the cosine of the incidence angle (as for triangles:
// seen along the ray, the strip is that much narrower).
#include "kernels/intersect_ribbon.h"
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

// What the host packs (scenes/prim_table.cpp): the normal unit length, in double.
K::Ribbon kribbon(const masq::RibbonPrim& r) {
  glm::dvec3 n(r.n);
  glm::vec3 nu = glm::length(n) > 0 ? glm::vec3(n / glm::length(n)) : glm::vec3(0.0f);
  return {{r.p0.x, r.p0.y, r.p0.z}, r.r0, {r.p1.x, r.p1.y, r.p1.z}, r.r1, {nu.x, nu.y, nu.z}, 0};
}

struct Frame {
  Vld p0, a, w, nrm; // axis start, axis, unit width direction, unit plane normal
  ld r0, r1;
};
Frame frame_of(const masq::RibbonPrim& r) {
  Frame f{to_ld(r.p0), to_ld(r.p1) - to_ld(r.p0), {}, {}, r.r0, r.r1};
  f.w = unitl(crossl(to_ld(r.n), f.a));
  f.nrm = unitl(crossl(f.a, f.w));
  return f;
}
Vld at(const Frame& f, ld s, ld v) { return f.p0 + s * f.a + (v * (f.r0 + s * (f.r1 - f.r0))) * f.w; }

TEST(Intersectors, RibbonsMatchOracle) {
  Rng rng(0x51bb0);
  std::printf("ribbons: length L, origin distance D, translation T\n");
  Tally robust_all, fast_all;
  StartTally surface_steep;
  for (ld T : {0.0L, 1e5L})
    for (ld L : {1e-3L, 1.0L})
      for (ld dist_l : {1.0L, 1e2L, 1e4L}) {
        if (T > 0 && L < 1) continue; // the 1e5 grid (2^-7) would collapse the ribbon
        Tally robust, fast;
        for (int k = 0; k < 20; ++k) {
          Vld base = Vld{uni(rng, -1, 1), uni(rng, -1, 1), uni(rng, -1, 1)} + Vld{T, T, T};
          Vld axis = rand_unit(rng), n = rand_unit(rng);
          if (lenl(crossl(axis, n)) < 0.1L) continue; // well-defined width directions here
          masq::RibbonPrim rb{to_f(base), float(L * uni(rng, 0.02, 0.3)), to_f(base + L * axis),
                              float(L * uni(rng, 0.02, 0.3)), to_f(uni(rng, 0.1, 10) * n)};
          Frame f = frame_of(rb);
          ld rmax = std::max<ld>(rb.r0, rb.r1), rmin = std::min<ld>(rb.r0, rb.r1);
          Vld c = f.p0 + 0.5L * f.a;
          for (int i = 0; i < 150; ++i) {
            // Aim at s in [-0.2, 1.2], v in [-1.3, 1.3] half-widths; half of them within
            // 1e-3..1e-1 of a long edge.
            ld s = uni(rng, -0.2, 1.2), v = uni(rng, -1.3, 1.3);
            if (i % 2 == 0) {
              s = uni(rng, 0, 1);
              v = (1 + log_uni(rng, 1e-3, 1e-1) * (uni(rng, 0, 1) < 0.5 ? -1 : 1)) * (i % 4 == 0 ? 1 : -1);
            }
            Vld aim = at(f, s, v);
            Vld o = aim + (dist_l * L) * rand_unit(rng);
            auto [of, df] = aimed_ray(o, aim, rng);
            PrimRay ray = ld_ray(of, df);
            PrimResult ref = masq::oracle::oracle_ribbon(rb, ray);
            ld cosi = std::max<ld>(std::fabs(dotl(f.nrm, ray.d)) / lenl(ray.d), 1e-6L);
            Scale sc{c, lenl(f.a), rmax * cosi, kInfL, rmin};
            compare(KV::intersect_ribbon(kribbon(rb), of, df, 0, kInfF), ref, ray, sc, robust);
            compare(KV::intersect_ribbon_fast(kribbon(rb), of, df, 0, kInfF), ref, ray, sc, fast);
          }
          // Rays leaving a point of the ribbon (near the world origin) must not hit it again.
          for (int i = 0; i < (T == 0 && L == 1 ? 50 : 0); ++i) {
            Vld pt = at(f, uni(rng, 0.05, 0.95), uni(rng, -0.9, 0.9));
            glm::vec3 of = to_f(pt);
            Vld dir = unitl((uni(rng, 0, 1) < 0.5 ? -1.0L : 1.0L) * f.nrm + uni(rng, 0, 0.55) * rand_perp(rng, f.nrm));
            glm::vec3 df = to_f(log_uni(rng, 1e-2, 1e2) * dir);
            Vld dl = to_ld(df);
            ld tcross = -dotl(to_ld(of) - pt, f.nrm) / dotl(dl, f.nrm);
            ld tself = masq::oracle::self_window_t(0, to_ld(of) - c, dotl(dl, dl), lenl(f.a));
            surface_steep.add(tcross, tself, 0, KV::intersect_ribbon(kribbon(rb), of, df, 0, kInfF).hit,
                              masq::oracle::oracle_ribbon(rb, ld_ray(of, df)).hit);
          }
        }
        std::printf("  T %6.0Lg L %5.0Lg D/L %5.0Lg | %5ld rays, band %5.1f%% | robust %.1e (raw %.1e) | fast raw %.2f%% "
                    "(outside band %.2f%%)\n",
                    T, L, dist_l, robust.n, 100 * robust.amb_rate(), robust.rate(), robust.rate_raw(),
                    100 * fast.rate_raw(), 100 * fast.rate());
        robust_all.add(robust);
        fast_all.add(fast);
      }
  expect_robust(robust_all, "ribbons");
  std::printf("textbook plane crossing: %.3f%% raw, %.2e outside the band\n", 100 * fast_all.rate_raw(),
              fast_all.rate());
  surface_steep.check("ribbons, rays from the surface, >= 60 deg from the plane");
}

// Ribbons without a surface never hit, in the kernel and in the oracle; a ribbon
// narrowing to a point (r1 = 0) is a triangle, hit like any other.
TEST(Intersectors, DegenerateRibbonsMatchOracle) {
  Rng rng(0x51bb1);
  const glm::vec3 p0(0.3f, -0.2f, 0.7f), axis = glm::normalize(glm::vec3(1, 2, 3));
  const glm::vec3 side = glm::normalize(glm::cross(axis, glm::vec3(0, 0, 1)));
  struct Named {
    const char* name;
    masq::RibbonPrim p;
    bool surface;
  };
  const Named prims[] = {
      {"normal along the axis", {p0, 0.1f, p0 + axis, 0.1f, 3.0f * axis}, false},
      {"normal 1e-5 rad off the axis", {p0, 0.1f, p0 + axis, 0.1f, axis + 1e-5f * side}, false},
      {"zero normal", {p0, 0.1f, p0 + axis, 0.1f, glm::vec3(0.0f)}, false},
      {"zero length", {p0, 0.1f, p0, 0.1f, side}, false},
      {"zero widths", {p0, 0.0f, p0 + axis, 0.0f, side}, false},
      {"narrowing to a point", {p0, 0.2f, p0 + axis, 0.0f, side}, true},
  };
  for (const Named& pr : prims) {
    long hits = 0, oracle_hits = 0, flips = 0, n = 0;
    Vld c = to_ld(pr.p.p0) + 0.5L * (to_ld(pr.p.p1) - to_ld(pr.p.p0));
    for (int i = 0; i < 2000; ++i) {
      Vld aim = c + uni(rng, 0, 0.6) * rand_unit(rng);
      auto [of, df] = aimed_ray(aim + 3.0L * rand_unit(rng), aim, rng);
      PrimResult ref = masq::oracle::oracle_ribbon(pr.p, ld_ray(of, df));
      KV::PrimHit h = KV::intersect_ribbon(kribbon(pr.p), of, df, 0, kInfF);
      ++n;
      hits += h.hit;
      oracle_hits += ref.hit;
      // Flips count only clear of the edges (the band of tests/intersector_compare.h).
      if ((h.hit != 0) != ref.hit && ref.clearance > 1e-3L) ++flips;
    }
    std::printf("%-30s %ld rays: kernel %ld hits, oracle %ld, %ld flips clear of the edges\n", pr.name, n, hits,
                oracle_hits, flips);
    if (!pr.surface) {
      EXPECT_EQ(hits, 0) << pr.name;
      EXPECT_EQ(oracle_hits, 0) << pr.name;
    } else {
      EXPECT_GT(oracle_hits, 100) << pr.name;
      EXPECT_EQ(flips, 0) << pr.name;
    }
  }
}

} // namespace
