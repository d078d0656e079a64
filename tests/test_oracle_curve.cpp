// The long-double oracle's swept-sphere curve, checked against hand-computed answers,
// against the capsule oracle on straight curves, and against brute-force unions of many
// small balls along the curve (an independent discretisation of the swept solid).
#include "oracle/oracle_prims.h"
#include "tests/oracle_test_util.h"
#include <gtest/gtest.h>
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <vector>

using namespace masq;
using namespace masq::oracle;
using namespace masq::test;

// ---------------------------------------------------------------- curve

TEST(OracleCurve, HandComputedStraightCurve) {
  CurvePrim c = straight_curve({-1.5f, 0, 0}, {1.5f, 0, 0}, 0.25f);
  PrimResult h = oracle_curve(c, ray({0.3L, 0, -5}, {0, 0, 1}));
  ASSERT_TRUE(h.hit);
  EXPECT_NEAR(double(h.t), 4.75, 1e-15);
  expect_normal(h, {0, 0, -1}, 1e-12L);
  EXPECT_NEAR(double(h.u), 0.6, 1e-7);
  // Round end: the sphere at (1.5, 0, 0).
  PrimResult e = oracle_curve(c, ray({1.6L, 0, -5}, {0, 0, 1}));
  ASSERT_TRUE(e.hit);
  EXPECT_NEAR(double(e.t), 5 - std::sqrt(0.0525), 1e-15);
  EXPECT_NEAR(double(e.u), 1.0, 0);
  // Inside, exit through the side; on the surface going outward: miss; non-unit d.
  PrimResult in = oracle_curve(c, ray({0, 0, 0}, {0, 0, 3}));
  ASSERT_TRUE(in.hit);
  EXPECT_NEAR(double(in.t), 0.25 / 3, 1e-16);
  expect_normal(in, {0, 0, 1}, 1e-12L);
  EXPECT_FALSE(oracle_curve(c, ray({0, 0, -0.25L}, {0, 0, -1})).hit);
  PrimResult onin = oracle_curve(c, ray({0, 0, -0.25L}, {0, 0, 1}));
  ASSERT_TRUE(onin.hit);
  EXPECT_NEAR(double(onin.t), 0.5, 1e-15);
  // Along the axis from outside: the round end's pole.
  PrimResult ax = oracle_curve(c, ray({-3, 0, 0}, {2, 0, 0}));
  ASSERT_TRUE(ax.hit);
  EXPECT_NEAR(double(ax.t), 1.25 / 2, 1e-15);
  expect_normal(ax, {-1, 0, 0}, 1e-12L);
}

TEST(OracleCurve, StraightCurveEqualsCapsule) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<float> u(-1, 1);
  int hits = 0, compared = 0;
  for (int i = 0; i < 3000; ++i) {
    glm::vec3 a(u(rng), u(rng), u(rng));
    glm::vec3 step(u(rng), u(rng), u(rng));
    // Control points a + k step (exact in float for these dyadic multiples), ends a, a + 3 step.
    step = glm::vec3(glm::ivec3(step * 1024.0f)) / 1024.0f;
    a = glm::vec3(glm::ivec3(a * 1024.0f)) / 1024.0f;
    CurvePrim c;
    for (int k = 0; k < 4; ++k) c.p[k] = a + float(k) * step;
    c.radius = 0.02f + 0.2f * std::abs(u(rng));
    CapsulePrim cap{c.p[0], c.p[3], c.radius};
    PrimRay ry = aimed_ray(rng, glm::mix(c.p[0], c.p[3], 0.5f + 0.7f * u(rng)), c.radius);
    if (i % 4 == 0) { // start inside
      ld s = 0.5L + 0.4L * u(rng);
      ry.o = {a.x + 3 * s * step.x, a.y + 3 * s * step.y, a.z + 3 * s * step.z};
    }
    PrimResult k = oracle_capsule(cap, ry), cv = oracle_curve(c, ry);
    if (k.clearance < 1e-9L) continue;
    ++compared;
    ASSERT_EQ(k.hit, cv.hit) << i;
    EXPECT_NEAR(double(cv.clearance), double(k.clearance), 1e-9 * std::max<double>(1, double(k.clearance))) << i;
    if (!k.hit) continue;
    ++hits;
    EXPECT_NEAR(double(cv.t), double(k.t), 1e-12 * double(k.t)) << i;
    EXPECT_GT(double(dotl(cv.normal, k.normal)), 1 - 1e-9) << i;
  }
  EXPECT_GT(compared, 2900);
  EXPECT_GT(hits, 1500);
}

TEST(OracleCurve, SilhouetteRaysOfAStraightCurveAreNotLost) {
  // Rays passing the axis at r (1 - 1e-7): the hit s-interval is ~1e-3.5 wide; still hit.
  CurvePrim c = straight_curve({-1.5f, 0, 0}, {1.5f, 0, 0}, 0.25f);
  for (ld eps : {1e-4L, 1e-7L, 1e-10L}) {
    for (ld x : {-1.2L, 0.1L, 1.4L}) {
      PrimResult h = oracle_curve(c, ray({x, 0.25L * (1 - eps), -5}, {0, 0, 1}));
      ASSERT_TRUE(h.hit) << double(eps) << " " << double(x);
      ld z = 0.25L * std::sqrt(eps * (2 - eps));
      EXPECT_NEAR(double(h.t), double(5 - z), 1e-15) << double(eps);
      EXPECT_NEAR(double(h.clearance), double(eps), 1e-12);
      EXPECT_FALSE(oracle_curve(c, ray({x, 0.25L * (1 + eps), -5}, {0, 0, 1})).hit);
    }
  }
}

TEST(OracleCurve, CoincidentPointsAreASphere) {
  CurvePrim c;
  c.p = {glm::vec3(0.5f, 0, 0), glm::vec3(0.5f, 0, 0), glm::vec3(0.5f, 0, 0), glm::vec3(0.5f, 0, 0)};
  c.radius = 0.5f;
  std::mt19937_64 rng(5);
  for (int i = 0; i < 200; ++i) {
    PrimRay ry = aimed_ray(rng, c.p[0], 0.5);
    PrimResult a = oracle_curve(c, ry), b = oracle_sphere({c.p[0], 0.5f}, ry);
    ASSERT_EQ(a.hit, b.hit);
    if (a.hit) {
      EXPECT_EQ(double(a.t), double(b.t));
    }
  }
  PrimResult h = oracle_curve(c, ray({0.8L, 0, -5}, {0, 0, 1}));
  ASSERT_TRUE(h.hit);
  EXPECT_NEAR(double(h.t), 4.6, 1e-15);
}

TEST(OracleCurve, ZeroRadiusAndInvalidRaysMiss) {
  CurvePrim c = straight_curve({-1, 0, 0}, {1, 0, 0}, 0.0f);
  EXPECT_FALSE(oracle_curve(c, ray({0, 0, -5}, {0, 0, 1})).hit);
  c.radius = -0.5f;
  EXPECT_FALSE(oracle_curve(c, ray({0, 0, -5}, {0, 0, 1})).hit);
  c.radius = 0.5f;
  EXPECT_TRUE(oracle_curve(c, ray({0, 0, -5}, {0, 0, 1})).hit);
  EXPECT_FALSE(oracle_curve(c, ray({0, 0, -5}, {0, 0, 0})).hit);
  EXPECT_FALSE(oracle_curve(c, ray({0, 0, -5}, {0, 0, 1}, 1, 0)).hit);
  EXPECT_FALSE(oracle_curve(c, ray({0, std::numeric_limits<ld>::quiet_NaN(), -5}, {0, 0, 1})).hit);
  EXPECT_FALSE(oracle_curve(c, ray({0, 0, -5}, {0, 0, 1}, 0, 4)).hit);
}

TEST(OracleCurve, UShapedCurveSecondEntry) {
  // A U in the xz-plane; a ray along x at z = 0.9 crosses both arms: it enters, exits,
  // and enters again. Restarting past each crossing finds the next one.
  CurvePrim c;
  c.p = {glm::vec3(-1, 0, 1), glm::vec3(-1, 0, -1), glm::vec3(1, 0, -1), glm::vec3(1, 0, 1)};
  c.radius = 0.05f;
  PrimRay ry = ray({-3, 0, 0.9L}, {1, 0, 0});
  PrimResult first = oracle_curve(c, ry);
  ASSERT_TRUE(first.hit);
  EXPECT_LT(double(first.t), 2.2);
  EXPECT_LT(double(first.u), 0.2);
  // Start inside the first arm: exit, then from the gap the second arm's entry.
  PrimResult exit = oracle_curve(c, ray({-3, 0, 0.9L}, {1, 0, 0}, first.t + 0.01L));
  ASSERT_TRUE(exit.hit);
  EXPECT_GT(double(exit.normal.x), 0.5);
  PrimResult second = oracle_curve(c, ray({-3, 0, 0.9L}, {1, 0, 0}, exit.t + 0.01L));
  ASSERT_TRUE(second.hit);
  EXPECT_GT(double(second.t), 3.8);
  EXPECT_LT(double(second.normal.x), -0.5);
  EXPECT_GT(double(second.u), 0.8);
}

// A curve against the union of 20000 balls along it. The sampled union lies inside the
// swept solid, so its first entry is never before the oracle's and its first exit (from
// a start inside) never after; the dip between neighbouring balls (spacing D: D^2 / 8r;
// along a ray meeting the surface obliquely, which clearance >= 1e-3 limits, up to ~25
// times that) bounds the difference.
struct UnionStats {
  int compared = 0, hits = 0, exits = 0;
  double worst_entry = 0, worst_exit = 0, worst_clearance = 0;
};

void check_against_ball_union(const CurvePrim& c, std::mt19937_64& rng, int rays, UnionStats& st) {
  std::uniform_real_distribution<float> u(-1, 1);
  const int n = 20000;
  std::vector<Vld> cs(n);
  std::vector<ld> rs(n, c.radius);
  for (int k = 0; k < n; ++k) {
    // Long-double Bernstein evaluation.
    ld s = ld(k) / (n - 1), w[4] = {(1 - s) * (1 - s) * (1 - s), 3 * s * (1 - s) * (1 - s), 3 * s * s * (1 - s), s * s * s};
    for (int j = 0; j < 4; ++j) {
      cs[k].x += w[j] * c.p[j].x;
      cs[k].y += w[j] * c.p[j].y;
      cs[k].z += w[j] * c.p[j].z;
    }
  }
  ld spacing = 0;
  for (int k = 1; k < n; ++k) spacing = std::max(spacing, std::sqrt(dotl(sub(cs[k], cs[k - 1]), sub(cs[k], cs[k - 1]))));
  const double tol = double(50 * spacing * spacing / (8 * c.radius)) + 1e-12;
  for (int i = 0; i < rays; ++i) {
    PrimRay ry = aimed_ray(rng, bezier(c, 0.5 + 0.55 * u(rng)), c.radius);
    PrimResult o = oracle_curve(c, ry);
    UnionHit s = ball_union_entry(cs, rs, ry);
    // Clearance: the sampled minimum distance from the ray (t >= 0) to the curve is never
    // below the true one, and above it by at most half a spacing (a sample lies that
    // close to the nearest curve point), ~spacing^2 / distance away from the curve.
    ld sampled = kInf, dd = dotl(ry.d, ry.d);
    for (const Vld& q : cs) {
      ld t = std::max<ld>(0, dotl(sub(q, ry.o), ry.d) / dd);
      Vld diff = sub(q, {ry.o.x + t * ry.d.x, ry.o.y + t * ry.d.y, ry.o.z + t * ry.d.z});
      sampled = std::min(sampled, std::sqrt(dotl(diff, diff)));
    }
    ld best = c.radius * (o.hit ? 1 - o.clearance : 1 + o.clearance);
    EXPECT_GE(double(sampled), double(best - 1e-12L)) << i;
    EXPECT_LT(double(sampled - best), double(std::min(0.51L * spacing, spacing * spacing / best) + 1e-12L)) << i;
    st.worst_clearance = std::max(st.worst_clearance, double((sampled - best) / c.radius));
    if (o.clearance < 1e-3L) continue;
    ++st.compared;
    ASSERT_EQ(o.hit, s.t < kInf) << i;
    if (!o.hit) continue;
    ++st.hits;
    ld dl = std::sqrt(dotl(ry.d, ry.d));
    EXPECT_GE(double(s.t), double(o.t - 1e-12L)) << i;
    EXPECT_LT(double((s.t - o.t) * dl), tol) << i;
    st.worst_entry = std::max(st.worst_entry, double((s.t - o.t) * dl / c.radius));
    EXPECT_GT(double(dotl(s.n, o.normal) / c.radius), 0.999) << i;
    // u: the hit point is at distance r from C(u).
    glm::vec3 cu = bezier(c, double(o.u));
    Vld hp{ry.o.x + o.t * ry.d.x, ry.o.y + o.t * ry.d.y, ry.o.z + o.t * ry.d.z};
    Vld off = sub(hp, v(cu));
    EXPECT_NEAR(double(std::sqrt(dotl(off, off))), c.radius, 1e-5 * c.radius);
    // The same line started inside the solid (abeam the centre of the entry ball): its exit.
    PrimRay in = ry;
    ld tc = dotl(sub(cs[s.ball], ry.o), ry.d) / (dl * dl);
    in.o = {ry.o.x + tc * ry.d.x, ry.o.y + tc * ry.d.y, ry.o.z + tc * ry.d.z};
    PrimResult x = oracle_curve(c, in);
    ld ex = ball_union_exit(cs, rs, in);
    ASSERT_TRUE(x.hit) << i;
    EXPECT_LE(double(ex), double(x.t + 1e-12L)) << i;
    EXPECT_LT(double((x.t - ex) * dl), tol) << i;
    st.worst_exit = std::max(st.worst_exit, double((x.t - ex) * dl / c.radius));
    ++st.exits;
  }
}

TEST(OracleCurve, MatchesUnionOfSampledBalls) {
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<float> u(-1, 1);
  UnionStats st;
  for (int prim = 0; prim < 8; ++prim) {
    SCOPED_TRACE(prim);
    CurvePrim c;
    for (int k = 0; k < 4; ++k) c.p[k] = glm::vec3(u(rng), u(rng), u(rng));
    c.radius = 0.03f + 0.15f * std::abs(u(rng));
    check_against_ball_union(c, rng, 60, st);
  }
  std::printf("sampled-ball union vs oracle: worst entry %.3g r, exit %.3g r, clearance %.3g r (%d exits)\n",
              st.worst_entry, st.worst_exit, st.worst_clearance, st.exits);
  EXPECT_GT(st.compared, 350);
  EXPECT_GT(st.hits, 150);
}

TEST(OracleCurve, DegenerateShapesMatchUnionOfSampledBalls) {
  std::mt19937_64 rng(2);
  const glm::vec3 A(-1, 0, 0), B(1, 0.5f, 0), C(0.2f, 1, 0.3f), D(1, -0.5f, 0.2f);
  const float e = 1e-6f;
  const std::array<glm::vec3, 4> shapes[] = {
      {A, B, A, B},                                    // out and back (self-overlapping)
      {A, A, B, B},                                    // zero tangent at both ends
      {A, C, B, A},                                    // closed loop
      {A, B, C, D},                                    // self-intersecting in projection
      {A, D, B, C},                                    // cusp-like
      {A, A + glm::vec3(e, 0, 0), A + glm::vec3(0, e, 0), A + glm::vec3(0, 0, e)}, // nearly a point
      {A, glm::mix(A, B, 0.3f) + glm::vec3(0, 1e-4f, 0), glm::mix(A, B, 0.7f), B}, // nearly straight
  };
  UnionStats st;
  int k = 0;
  for (const auto& p : shapes) {
    SCOPED_TRACE(k++);
    for (float r : {0.05f, 0.3f}) {
      CurvePrim c{p, r};
      check_against_ball_union(c, rng, 40, st);
    }
  }
  std::printf("degenerate shapes: worst entry %.3g r, worst exit %.3g r (%d exits)\n", st.worst_entry, st.worst_exit,
              st.exits);
  EXPECT_GT(st.hits, 250);
}

TEST(OracleCurve, TimePerRay) {
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<float> u(-1, 1);
  CurvePrim c;
  for (int k = 0; k < 4; ++k) c.p[k] = glm::vec3(u(rng), u(rng), u(rng));
  c.radius = 0.01f;
  // Hit rays aimed at the curve; near misses passing within 1e-3 r .. r of the surface.
  std::vector<PrimRay> hit_rays, miss_rays;
  while (hit_rays.size() < 4000 || miss_rays.size() < 4000) {
    PrimRay ry = aimed_ray(rng, bezier(c, 0.5 + 0.5 * u(rng)), c.radius);
    PrimResult o = oracle_curve(c, ry);
    if (o.hit && hit_rays.size() < 4000) hit_rays.push_back(ry);
    if (!o.hit && o.clearance < 1 && miss_rays.size() < 4000) miss_rays.push_back(ry);
  }
  for (auto* set : {&hit_rays, &miss_rays}) {
    auto t0 = std::chrono::steady_clock::now();
    int n = 0;
    for (const PrimRay& ry : *set) n += oracle_curve(c, ry).hit;
    double us = std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - t0).count() / set->size();
    std::printf("oracle_curve: %.2f us per %s ray\n", us, set == &hit_rays ? "hit" : "near-miss");
    EXPECT_EQ(n, set == &hit_rays ? int(set->size()) : 0);
    EXPECT_LT(us, 1000.0); // a regression guard only; the target is < 50 us
  }
}
