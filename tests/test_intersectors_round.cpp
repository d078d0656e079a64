// Round primitive intersectors (kernels/intersect_{capsule,round_cone,sphere}*.h,
// compiled as C++) against the independent long-double oracle (oracle/oracle_prims.h),
// one ray and one primitive at a time. Robust variants are asserted; fast variants
// (Quilez as written, textbook sphere) are measured and printed (they exist for speed
// comparisons), and asserted only where their digits suffice (close, short primitives).
// The band of legitimate fp32 disagreement: tests/intersector_compare.h.
#include "tests/round_prims.h"
#include <gtest/gtest.h>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <utility>
#include <vector>

using namespace masq::test;

namespace {

void check_kind(Kind kind) {
  Rng rng(0x5eed0000u + unsigned(kind));
  print_header();
  Result total, hard, easy;
  std::vector<std::pair<ld, Result>> by_dist;
  for (const Config& cf : configs(kind)) {
    Result r;
    for (int prim = 0; prim < 4; ++prim) r.add(run_prim(make_round(cf, rng), cf.dist_r, 500, 200, rng));
    print_row(kind_name(kind), cf.translate, cf.len_r, cf.dist_r, r);
    total.add(r);
    auto it = std::find_if(by_dist.begin(), by_dist.end(), [&](const auto& e) { return e.first == cf.dist_r; });
    (it == by_dist.end() ? by_dist.emplace_back(cf.dist_r, Result{}).second : it->second).add(r);
    // The range the architecture notes measured Quilez's capsule on: 1e2..1e5 radii.
    if (cf.dist_r >= 1e2L && cf.dist_r <= 1e5L) hard.add(r);
    if (cf.dist_r <= 1e1L && cf.len_r <= 1) easy.add(r);
  }
  std::printf("%s silhouette rays by distance (all lengths, both translations): raw disagreement robust / fast\n",
              kind_name(kind));
  for (const auto& [dr, r] : by_dist)
    std::printf("  D/r %6.0Lg: robust %7.3f%% (outside band %.1e, band %5.1f%%)   fast %6.2f%%\n", dr,
                100 * r.robust_sil.rate_raw(), r.robust_sil.rate(), 100 * r.robust_sil.amb_rate(),
                100 * r.fast_sil.rate_raw());
  std::printf("%s silhouette rays from 1e2..1e5 radii: fast (as written) disagrees on %.1f%% (%.1f%% outside the "
              "band); robust on %.3f%% (%.1e outside the band)\n",
              kind_name(kind), 100 * hard.fast_sil.rate_raw(), 100 * hard.fast_sil.rate(),
              100 * hard.robust_sil.rate_raw(), hard.robust_sil.rate());
  Tally robust = total.robust_sil;
  robust.add(total.robust_rand);
  expect_robust(robust, kind_name(kind));
  // Where its digits suffice (close and short) the fast variant must be right too:
  // this checks its adaptation to non-unit directions, both roots and the contract.
  Tally fast_easy = easy.fast_sil;
  fast_easy.add(easy.fast_rand);
  EXPECT_EQ(fast_easy.flips, 0) << kind_name(kind) << ": fast variant, easy rays";
  EXPECT_EQ(fast_easy.t_bad + fast_easy.n_bad + fast_easy.u_bad, 0) << kind_name(kind) << ": fast variant, easy rays";
  // The hard range must really be hard: the test would prove nothing if its rays did
  // not trouble the textbook formula (for the sphere: b^2 - c).
  EXPECT_GT(hard.fast_sil.rate_raw(), 10 * hard.robust_sil.rate_raw() + 1e-2) << kind_name(kind);
}

TEST(Intersectors, CapsuleMatchesOracle) { check_kind(Kind::Capsule); }
TEST(Intersectors, RoundConeMatchesOracle) { check_kind(Kind::Cone); }
TEST(Intersectors, SphereMatchesOracle) { check_kind(Kind::Sphere); }

// ---------------------------------------------------------------- degenerate shapes

Round cone(glm::vec3 a, float ra, glm::vec3 b, float rb) { return {Kind::Cone, a, b, ra, rb}; }

TEST(Intersectors, DegenerateShapesMatchOracle) {
  Rng rng(0xde9e);
  glm::vec3 c(0.3f, -0.2f, 0.7f), w = glm::normalize(glm::vec3(1, 2, 3));
  float r = 1e-3f;
  struct Named {
    const char* name;
    Round p;
  };
  std::vector<Named> prims = {
      {"capsule, zero length", {Kind::Capsule, c, c, r, r}},
      {"cone, zero length", cone(c, r, c, 0.5f * r)},
      {"cone, b inside a", cone(c, r, c + 0.3f * r * w, 0.5f * r)},
      {"cone, a inside b", cone(c, 0.2f * r, c + 0.5f * r * w, r)},
      {"cone, nearly contained", cone(c, r, c + 0.5005f * r * w, 0.5f * r)},
      {"cone, equal radii", cone(c, r, c + 30.0f * r * w, r)},
      {"cone, point end", cone(c, r, c + 10.0f * r * w, 0.0f)},
      {"cone, negative end", cone(c, -r, c + 10.0f * r * w, r)},
      {"cone, long point end", cone(c, r, c + 1e4f * r * w, 0.0f)},
  };
  print_header();
  Tally robust;
  for (const Named& nm : prims)
    for (ld dr : {1e1L, 1e3L}) {
      Result res = run_prim(nm.p, dr, 1000, 500, rng);
      print_row(kind_name(nm.p.kind), 0, lenl(to_ld(nm.p.b) - to_ld(nm.p.a)) / r, dr, res);
      std::printf("    (%s)\n", nm.name);
      robust.add(res.robust_sil);
      robust.add(res.robust_rand);
    }
  expect_robust(robust, "degenerate shapes");
}

// The degenerate cases give exactly the simpler primitive's surface.
TEST(Intersectors, DegenerateShapesAgreeWithSimplerKernels) {
  Rng rng(0x51);
  glm::vec3 c(0.3f, -0.2f, 0.7f), w = glm::normalize(glm::vec3(-1, 2, 0.5f));
  float r = 0.01f;
  Round sphere{Kind::Sphere, c, c, r, r};
  Round zero_capsule{Kind::Capsule, c, c, r, r};
  Round contained = cone(c, r, c + 0.4f * r * w, 0.5f * r);
  Round zero_cone = cone(c + 0.f * w, 0.3f * r, c, r);
  Round capsule{Kind::Capsule, c, c + 20.0f * r * w, r, r};
  Round equal = cone(c, r, c + 20.0f * r * w, r);
  int bad = 0, hits = 0;
  for (int i = 0; i < 20000; ++i) {
    Vld o = to_ld(c) + (5 * ld(r)) * rand_unit(rng);
    Vld aim = to_ld(c) + (ld(r) * 1.2L * std::cbrt(uni(rng, 0, 1))) * rand_unit(rng) + uni(rng, 0, 20 * r) * to_ld(w);
    auto [of, df] = aimed_ray(o, aim, rng);
    auto same = [&](const Round& x, const Round& y, float rel) {
      for (int fast = 0; fast < 2; ++fast) {
        KV::PrimHit hx = run_kernel(x, fast, of, df), hy = run_kernel(y, fast, of, df);
        hits += hx.hit;
        if (hx.hit != hy.hit || (hx.hit && std::fabs(hx.t - hy.t) * glm::length(df) > rel * r)) ++bad;
      }
    };
    same(zero_capsule, sphere, 1e-5f);
    same(contained, sphere, 1e-5f);
    same(zero_cone, sphere, 1e-5f);
    same(equal, capsule, 1e-4f); // different formulas: agree up to rounding (and silhouettes)
  }
  std::printf("degenerate vs simpler kernels: %d hits, %d disagreements\n", hits, bad);
  EXPECT_GT(hits, 20000);
  EXPECT_LE(bad, 20); // equal-radii cone vs capsule may differ on a handful of silhouette rays
}

TEST(Intersectors, NoSurfaceOrInvalidRayMisses) {
  Rng rng(0x0);
  glm::vec3 c(0.1f, 0.2f, 0.3f), w(0, 0, 1);
  float nan = std::numeric_limits<float>::quiet_NaN();
  std::vector<Round> none = {
      {Kind::Capsule, c, c + w, 0.0f, 0.0f},  {Kind::Capsule, c, c + w, -1.0f, -1.0f},
      {Kind::Capsule, c, c + w, nan, nan},    {Kind::Sphere, c, c, 0.0f, 0.0f},
      {Kind::Sphere, c, c, nan, nan},         {Kind::Sphere, c, c, -1.0f, -1.0f},
      cone(c, 0.0f, c + w, 0.0f),             cone(c, nan, c + w, -1.0f),
      cone(c, -1.0f, c + w, 0.0f),            cone(c, nan, c, nan),
  };
  int hits = 0, rays = 0;
  for (const Round& p : none)
    for (int i = 0; i < 200; ++i) {
      Vld o = to_ld(c) + 3.0L * rand_unit(rng);
      auto [of, df] = aimed_ray(o, to_ld(c) + uni(rng, 0, 1) * to_ld(w), rng);
      for (int fast = 0; fast < 2; ++fast) {
        hits += run_kernel(p, fast, of, df).hit;
        ++rays;
      }
    }
  // Invalid rays against real primitives (robust variants; the oracle's contract).
  std::vector<Round> some = {{Kind::Capsule, c, c + w, 0.5f, 0.5f}, {Kind::Sphere, c, c, 0.5f, 0.5f},
                             cone(c, 0.5f, c + w, 0.2f)};
  float inf = kInfF;
  glm::vec3 o(0.1f, 0.2f, -5.0f), d(0, 0, 1);
  for (const Round& p : some) {
    EXPECT_TRUE(run_kernel(p, false, o, d).hit) << kind_name(p.kind);
    hits += run_kernel(p, false, glm::vec3(nan, 0, 0), d).hit;
    hits += run_kernel(p, false, glm::vec3(inf, 0, 0), d).hit;
    hits += run_kernel(p, false, o, glm::vec3(0)).hit;
    hits += run_kernel(p, false, o, glm::vec3(nan, 0, 1)).hit;
    hits += run_kernel(p, false, o, d, nan, inf).hit;
    hits += run_kernel(p, false, o, d, 0, nan).hit;
    hits += run_kernel(p, false, o, d, 10, 1).hit;
    hits += run_kernel(p, false, o, d, 0, 4).hit; // the surface is beyond tmax
    rays += 8;
  }
  EXPECT_EQ(hits, 0) << "of " << rays;
}

// ---------------------------------------------------------------- self window and inside rays

// Rays from a surface point: going out they must miss, going in they must report the
// far exit. Rays from inside report the exit.
TEST(Intersectors, SelfWindowAndInsideRays) {
  Rng rng(0x5e1f);
  long fast_self = 0, fast_rays = 0, in_rays = 0;
  StartTally outward;
  Tally inward, inside;
  for (Kind kind : {Kind::Capsule, Kind::Cone, Kind::Sphere})
    for (ld r : {1e-2L, 1e-4L})
      for (ld lr : {0.0L, 10.0L, 1e3L}) {
        if (kind == Kind::Sphere && lr > 0) continue;
        for (int prim = 0; prim < 8; ++prim) {
          Round p = make_round({kind, r, kind == Kind::Cone ? std::max<ld>(lr, 1) : lr, 0, 0}, rng);
          Geo g = geometry(p);
          Scale sc = round_scale(g);
          for (int i = 0; i < 300; ++i) {
            SurfPt s = sample_surface(g, rng);
            glm::vec3 of = to_f(s.p);
            Vld tang = rand_perp(rng, s.n);
            ld slope = uni(rng, 0, 3); // up to ~72 degrees from the normal
            ld scale = log_uni(rng, 1e-2, 1e2);
            glm::vec3 d_out = to_f(scale * unitl(s.n + slope * tang));
            glm::vec3 d_in = to_f(scale * unitl((-1.0L) * s.n + slope * tang));
            Vld dl = to_ld(d_out);
            ld dn = dotl(dl, s.n), dd = dotl(dl, dl);
            ld tcross = -dotl(to_ld(of) - s.p, s.n) / dn;
            ld tself = masq::oracle::self_window_t(rmax(g), to_ld(of) - g.c, dd, g.len);
            ld e_t = 4 * kU * (lenl(to_ld(of) - g.c) + g.len + rmax(g)) / std::fabs(dn);
            outward.add(tcross, tself, e_t, run_kernel(p, false, of, d_out).hit,
                        run_oracle(p, ld_ray(of, d_out)).hit);
            compare(run_kernel(p, false, of, d_in), run_oracle(p, ld_ray(of, d_in)), ld_ray(of, d_in), sc, inward);
            ++in_rays;
            // Fast variants: a self hit is a hit on the way out, or t ~ 0 on the way in.
            KV::PrimHit fo = run_kernel(p, true, of, d_out), fi = run_kernel(p, true, of, d_in);
            fast_rays += 2;
            fast_self += fo.hit + (fi.hit && fi.t * glm::length(d_in) < 0.01f * float(rmin(g)));
            // From inside: a point of the ball at axial fraction q, well within it.
            ld q = uni(rng, 0, 1);
            ld rq = g.ball ? rmax(g) : g.ra + q * (g.rb - g.ra);
            Vld centre = g.ball ? (g.ra >= g.rb ? g.a : g.b) : g.a + q * (g.b - g.a);
            Vld pin = centre + (0.8L * rq * std::cbrt(uni(rng, 0, 1))) * rand_unit(rng);
            auto [oi, di] = aimed_ray(pin, pin + rand_unit(rng), rng);
            PrimRay ray = ld_ray(oi, di);
            compare(run_kernel(p, false, oi, di), run_oracle(p, ray), ray, sc, inside);
          }
        }
      }
  outward.check("capsule/cone/sphere, outward from the surface");
  std::printf("fast variants (no window): self hits on %.1f%% of %ld surface rays\n",
              100.0 * double(fast_self) / double(fast_rays), fast_rays);
  expect_robust(inward, "inward from the surface");
  EXPECT_EQ(inward.flips_raw, 0);
  EXPECT_EQ(inward.n, in_rays);
  expect_robust(inside, "from inside");
  EXPECT_EQ(inside.flips_raw, 0);
  EXPECT_EQ(inside.amb, 0);
}


// Issue 23: capsules 1e5..1e6 radii long reported false hits near their end caps, up to
// 0.12 r outside the surface, where a textbook fp32 cap does ~30x better: the side
// crossings were accepted 1e-6 (h + r) past the end (0.5 r at L = 1e6 r) and the caps
// were solved in the centre frame (error u (D + L)). Rays from 10..1e3 radii at points
// r (1 +- 1e-4..1e-1) from an endpoint on its outer hemisphere, against the oracle:
// outside the band of a ball at that distance, 4u (1 + (D + r) / r), with no length
// term, hit and miss must agree; likewise for the round cone (rb = 0.7 ra), whose
// balls and side are solved from the nearer ball's centre the same way.
TEST(Intersectors, LongCapsuleEndCapsMatchOracle) {
  Rng rng(0xe11dca95u);
  for (Kind kind : {Kind::Capsule, Kind::Cone})
  for (ld lr : {1e5L, 1e6L}) {
    long rays = 0, flips = 0;
    ld worst = 0; // largest oracle clearance / r of a flipped ray
    for (int prim = 0; prim < 8; ++prim) {
      const ld r = 1e-3L;
      Vld w = rand_unit(rng), c = {uni(rng, -1, 1), uni(rng, -1, 1), uni(rng, -1, 1)};
      const float rb = kind == Kind::Cone ? float(0.7L * r) : float(r);
      Round p{kind, to_f(c - (0.5L * lr * r) * w), to_f(c + (0.5L * lr * r) * w), float(r), rb};
      Geo g = geometry(p);
      for (int i = 0; i < 2000; ++i) {
        const bool at_b = i % 2 == 1;
        Vld end = at_b ? g.b : g.a, out = at_b ? g.w : (-1.0L) * g.w;
        Vld n = unitl(uni(rng, 0, 1) * out + rand_perp(rng, out)); // outer hemisphere
        ld eps = log_uni(rng, 1e-4L, 1e-1L) * (i % 4 < 2 ? 1 : -1);
        Vld target = end + ((at_b ? g.rb : g.ra) * (1 + eps)) * n;
        Vld dir = unitl(rand_perp(rng, n) + uni(rng, -0.3L, 0.3L) * n);
        ld dist = log_uni(rng, 10, 1e3) * r;
        glm::vec3 o = to_f(target - dist * dir), d = to_f(dir);
        PrimResult want = run_oracle(p, ld_ray(o, d));
        KV::PrimHit got = run_kernel(p, false, o, d);
        ++rays;
        if (want.clearance < 4 * kU * (1 + (dist + r) / r) || (got.hit != 0) == want.hit) continue;
        ++flips;
        worst = std::max(worst, want.clearance);
      }
    }
    std::printf("%s L/r %.0Le, end-cap rays: %ld of %ld flip outside the ball's band (worst clearance %.3Lg r)\n",
                kind_name(kind), lr, flips, rays, worst);
    EXPECT_EQ(flips, 0) << kind_name(kind) << " L/r " << double(lr) << ": worst clearance " << double(worst) << " r";
  }
}

} // namespace
