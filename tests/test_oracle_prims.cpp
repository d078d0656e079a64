// The long-double oracle's closed-form primitives (sphere, capsule, round cone, triangle),
// checked against hand-computed answers, against each other where the shapes coincide,
// and the round cone against a brute-force union of many small balls (an independent
// discretisation of the tangent-cone construction).
#include "oracle/oracle_prims.h"
#include "tests/oracle_test_util.h"
#include <gtest/gtest.h>
#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

using namespace masq;
using namespace masq::oracle;
using namespace masq::test;

// ---------------------------------------------------------------- sphere

TEST(OracleSphere, AxisAlignedHitAndNormal) {
  PrimResult h = oracle_sphere({{0, 0, 0}, 0.5f}, ray({0, 0, -5}, {0, 0, 1}));
  ASSERT_TRUE(h.hit);
  EXPECT_DOUBLE_EQ(double(h.t), 4.5);
  expect_normal(h, {0, 0, -1});
}

TEST(OracleSphere, NonUnitDirectionScalesT) {
  PrimResult h = oracle_sphere({{0, 0, 0}, 0.5f}, ray({0, 0, -5}, {0, 0, 4}));
  ASSERT_TRUE(h.hit);
  EXPECT_DOUBLE_EQ(double(h.t), 4.5 / 4);
  expect_normal(h, {0, 0, -1});
}

TEST(OracleSphere, OffAxisHandComputed) {
  // x = 0.3 through a sphere of radius 0.5: z = -sqrt(0.25 - 0.09) = -0.4.
  PrimResult h = oracle_sphere({{0, 0, 0}, 0.5f}, ray({0.3L, 0, -5}, {0, 0, 1}));
  ASSERT_TRUE(h.hit);
  EXPECT_NEAR(double(h.t), 4.6, 1e-15);
  expect_normal(h, {0.6L, 0, -0.8L}, 1e-15L);
}

TEST(OracleSphere, RayStartingInsideExits) {
  PrimResult h = oracle_sphere({{0, 0, 0}, 0.5f}, ray({0, 0, 0}, {0, 0, 1}));
  ASSERT_TRUE(h.hit);
  EXPECT_DOUBLE_EQ(double(h.t), 0.5);
  expect_normal(h, {0, 0, 1});
}

TEST(OracleSphere, SelfWindowOnSurface) {
  // On the surface going outward: the only crossing is the origin itself -> miss.
  EXPECT_FALSE(oracle_sphere({{0, 0, 0}, 0.5f}, ray({0, 0, -0.5L}, {0, 0, -1})).hit);
  // On the surface going inward: the far side, not the start.
  PrimResult h = oracle_sphere({{0, 0, 0}, 0.5f}, ray({0, 0, -0.5L}, {0, 0, 1}));
  ASSERT_TRUE(h.hit);
  EXPECT_DOUBLE_EQ(double(h.t), 1.0);
  // A crossing just beyond the window is reported, one just inside it is not.
  ld tw = self_window_t(0.5L, {0, 0, -0.5L}, 1);
  EXPECT_NEAR(double(tw), (0.5 / 1024 + 32 * 0.5 / 16777216.0), 1e-18);
  EXPECT_TRUE(oracle_sphere({{0, 0, 0}, 0.5f}, ray({0, 0, -0.5L - 1.01L * tw}, {0, 0, 1})).hit);
  PrimResult in = oracle_sphere({{0, 0, 0}, 0.5f}, ray({0, 0, -0.5L - 0.5L * tw}, {0, 0, 1}));
  ASSERT_TRUE(in.hit);
  EXPECT_GT(double(in.t), 0.9); // the exit, not the entry inside the window
}

TEST(OracleSphere, InvalidRaysAndZeroRadiusMiss) {
  const SpherePrim s{{0, 0, 0}, 0.5f};
  ld nan = std::numeric_limits<ld>::quiet_NaN();
  EXPECT_FALSE(oracle_sphere(s, ray({nan, 0, -5}, {0, 0, 1})).hit);
  EXPECT_FALSE(oracle_sphere(s, ray({0, 0, -5}, {0, nan, 1})).hit);
  EXPECT_FALSE(oracle_sphere(s, ray({0, 0, -5}, {0, 0, kInf})).hit);
  EXPECT_FALSE(oracle_sphere(s, ray({0, 0, -5}, {0, 0, 0})).hit);
  EXPECT_FALSE(oracle_sphere(s, ray({0, 0, -5}, {0, 0, 1}, 3, 2)).hit);
  EXPECT_FALSE(oracle_sphere(s, ray({0, 0, -5}, {0, 0, 1}, nan, 2)).hit);
  EXPECT_FALSE(oracle_sphere({{0, 0, 0}, 0.0f}, ray({0, 0, -5}, {0, 0, 1})).hit);
  EXPECT_FALSE(oracle_sphere({{0, 0, 0}, -1.0f}, ray({0, 0, -5}, {0, 0, 1})).hit);
  // tmax before the sphere, tmin beyond it.
  EXPECT_FALSE(oracle_sphere(s, ray({0, 0, -5}, {0, 0, 1}, 0, 4)).hit);
  EXPECT_FALSE(oracle_sphere(s, ray({0, 0, -5}, {0, 0, 1}, 5.6L, kInf)).hit);
  // tmin between entry and exit: the exit.
  PrimResult h = oracle_sphere(s, ray({0, 0, -5}, {0, 0, 1}, 5, kInf));
  ASSERT_TRUE(h.hit);
  EXPECT_DOUBLE_EQ(double(h.t), 5.5);
}

TEST(OracleSphere, Clearance) {
  // Passing at distance 0.5005 from the centre of a sphere of radius 0.5: 1e-3.
  PrimResult h = oracle_sphere({{0, 0, 0}, 0.5f}, ray({0.5005L, 0, -5}, {0, 0, 1}));
  EXPECT_FALSE(h.hit);
  EXPECT_NEAR(double(h.clearance), 1e-3, 1e-12);
  EXPECT_NEAR(double(h.t_near), 5.0, 1e-12);
  // The segment ends at t = 4 (z = -1): the nearest point is its end.
  PrimResult e = oracle_sphere({{0, 0, 0}, 0.5f}, ray({0.0L, 0, -5}, {0, 0, 1}, 0, 4));
  EXPECT_FALSE(e.hit);
  EXPECT_NEAR(double(e.clearance), 1.0, 1e-15);
  EXPECT_NEAR(double(e.t_near), 4.0, 1e-15);
}

// ---------------------------------------------------------------- capsule

TEST(OracleCapsule, SideAndCapHits) {
  const CapsulePrim c{{-1, 0, 0}, {1, 0, 0}, 0.25f};
  PrimResult h = oracle_capsule(c, ray({0.3L, 0, -5}, {0, 0, 1}));
  ASSERT_TRUE(h.hit);
  EXPECT_DOUBLE_EQ(double(h.t), 4.75);
  expect_normal(h, {0, 0, -1});
  EXPECT_NEAR(double(h.u), 0.65, 1e-8); // 0.3 in float
  // Beyond b: the end sphere, z = -sqrt(0.0625 - 0.01).
  PrimResult e = oracle_capsule(c, ray({1.1L, 0, -5}, {0, 0, 1}));
  ASSERT_TRUE(e.hit);
  EXPECT_NEAR(double(e.t), 5 - std::sqrt(0.0525), 1e-15);
  EXPECT_NEAR(double(e.u), 1.0, 0);
  // Along the axis from outside: the end sphere's pole.
  PrimResult ax = oracle_capsule(c, ray({-3, 0, 0}, {1, 0, 0}));
  ASSERT_TRUE(ax.hit);
  EXPECT_DOUBLE_EQ(double(ax.t), 1.75);
  expect_normal(ax, {-1, 0, 0});
}

TEST(OracleCapsule, InsideExitsAndSurfaceStartMisses) {
  const CapsulePrim c{{-1, 0, 0}, {1, 0, 0}, 0.25f};
  PrimResult h = oracle_capsule(c, ray({0, 0, 0}, {1, 0, 0}));
  ASSERT_TRUE(h.hit);
  EXPECT_DOUBLE_EQ(double(h.t), 1.25);
  expect_normal(h, {1, 0, 0});
  EXPECT_FALSE(oracle_capsule(c, ray({0, 0.25L, 0}, {0, 1, 0})).hit);
  PrimResult in = oracle_capsule(c, ray({0, 0.25L, 0}, {0, -2, 0}));
  ASSERT_TRUE(in.hit);
  EXPECT_DOUBLE_EQ(double(in.t), 0.25);
}

TEST(OracleCapsule, ZeroLengthIsSphereZeroRadiusMisses) {
  PrimResult h = oracle_capsule({{0, 0, 0}, {0, 0, 0}, 0.5f}, ray({0.3L, 0, -5}, {0, 0, 1}));
  ASSERT_TRUE(h.hit);
  EXPECT_NEAR(double(h.t), 4.6, 1e-15);
  EXPECT_FALSE(oracle_capsule({{-1, 0, 0}, {1, 0, 0}, 0.0f}, ray({0, 0, -5}, {0, 0, 1})).hit);
  EXPECT_FALSE(oracle_capsule({{-1, 0, 0}, {1, 0, 0}, 0.25f}, ray({0, 0, -5}, {0, 0, 0})).hit);
}

TEST(OracleCapsule, ClearanceOverTheSegment) {
  const CapsulePrim c{{-1, 0, 0}, {1, 0, 0}, 0.25f};
  PrimResult h = oracle_capsule(c, ray({0, 0.2505L, -5}, {0, 0, 1}));
  EXPECT_FALSE(h.hit);
  EXPECT_NEAR(double(h.clearance), 2e-3, 1e-12);
  // Segment ending at z = -1: distance sqrt(0.2505^2 + 1).
  PrimResult e = oracle_capsule(c, ray({0, 0.2505L, -5}, {0, 0, 1}, 0, 4));
  EXPECT_NEAR(double(e.clearance), (std::sqrt(0.2505 * 0.2505 + 1) - 0.25) / 0.25, 1e-12);
}

// ---------------------------------------------------------------- round cone

// a = 0, ra = 1, b = (1,0,0), rb = 0.4: sin(phi) = 0.6, cos(phi) = 0.8; the flank runs
// between x = 0.6 and x = 1.24 with radius (1 - 0.6 x) / 0.8 and normal (0.6, *, *).
const RoundConePrim kCone{{0, 0, 0}, 1.0f, {1, 0, 0}, 0.4f};

TEST(OracleRoundCone, FlankHandComputed) {
  PrimResult h = oracle_round_cone(kCone, ray({0.8L, 0, -10}, {0, 0, 1}));
  ASSERT_TRUE(h.hit);
  EXPECT_NEAR(double(h.t), 10 - 0.65, 2e-8); // 0.4f, 0.8 in float
  expect_normal(h, {0.6L, 0, -0.8L}, 1e-7L);
  EXPECT_NEAR(double(h.u), 0.8, 1e-7);
  // Same with exactly representable numbers: ra = 1, rb = 0.5, L = 2: s = 0.25.
  const RoundConePrim c2{{0, 0, 0}, 1.0f, {2, 0, 0}, 0.5f};
  ld s = 0.25L, c = std::sqrt(1 - s * s);
  PrimResult f = oracle_round_cone(c2, ray({1.0L, 0, -10}, {0, 0, 1}));
  ASSERT_TRUE(f.hit);
  EXPECT_NEAR(double(f.t), double(10 - (1 - s) / c), 1e-15);
  expect_normal(f, {s, 0, -c}, 1e-15L);
  // From above (+y side), non-unit direction.
  PrimResult g = oracle_round_cone(c2, ray({1.0L, 10, 0}, {0, -2, 0}));
  ASSERT_TRUE(g.hit);
  EXPECT_NEAR(double(g.t), double((10 - (1 - s) / c) / 2), 1e-15);
  expect_normal(g, {s, c, 0}, 1e-15L);
}

TEST(OracleRoundCone, CapsHandComputed) {
  // x = 0.3 < 0.6: sphere a's cap.
  PrimResult a = oracle_round_cone(kCone, ray({0.3L, 0, -10}, {0, 0, 1}));
  ASSERT_TRUE(a.hit);
  EXPECT_NEAR(double(a.t), 10 - std::sqrt(0.91), 1e-15);
  // x = 1.3 > 1.24: sphere b's cap (the flank extended would give 0.275, outside it).
  PrimResult b = oracle_round_cone(kCone, ray({1.3L, 0, -10}, {0, 0, 1}));
  ASSERT_TRUE(b.hit);
  EXPECT_NEAR(double(b.t), 10 - std::sqrt(0.4 * 0.4 - 0.09), 1e-7);
  // Beyond the tip.
  EXPECT_FALSE(oracle_round_cone(kCone, ray({1.45L, 0, -10}, {0, 0, 1})).hit);
  // Along the axis: the poles.
  PrimResult ax = oracle_round_cone(kCone, ray({-5, 0, 0}, {1, 0, 0}));
  ASSERT_TRUE(ax.hit);
  EXPECT_DOUBLE_EQ(double(ax.t), 4.0);
  PrimResult back = oracle_round_cone(kCone, ray({5, 0, 0}, {-1, 0, 0}));
  ASSERT_TRUE(back.hit);
  EXPECT_NEAR(double(back.t), 5 - 1.4, 1e-7);
}

TEST(OracleRoundCone, ContainedSphereIsTheBiggerSphere) {
  const RoundConePrim c{{0, 0, 0}, 1.0f, {0.25f, 0, 0}, 0.5f};
  PrimResult h = oracle_round_cone(c, ray({0.6L, 0, -5}, {0, 0, 1}));
  ASSERT_TRUE(h.hit);
  EXPECT_NEAR(double(h.t), 4.2, 1e-15);
  expect_normal(h, {0.6L, 0, -0.8L}, 1e-15L);
  // Swapped ends, and the internally tangent limit.
  PrimResult s = oracle_round_cone({{0.25f, 0, 0}, 0.5f, {0, 0, 0}, 1.0f}, ray({0.6L, 0, -5}, {0, 0, 1}));
  ASSERT_TRUE(s.hit);
  EXPECT_NEAR(double(s.t), 4.2, 1e-15);
  PrimResult t = oracle_round_cone({{0, 0, 0}, 1.0f, {0.5f, 0, 0}, 0.5f}, ray({0.6L, 0, -5}, {0, 0, 1}));
  ASSERT_TRUE(t.hit);
  EXPECT_NEAR(double(t.t), 4.2, 1e-15);
  // Inside exits through the big sphere.
  PrimResult in = oracle_round_cone(c, ray({0, 0, 0}, {0, 1, 0}));
  ASSERT_TRUE(in.hit);
  EXPECT_DOUBLE_EQ(double(in.t), 1.0);
}

TEST(OracleRoundCone, ClearanceIsTheGapToTheSolid) {
  // The line x = 0.8, z = -1 along y: the flank's outward normal there is (0.6, 0, -0.8),
  // so the gap is 0.6 * 0.8 + 0.8 * 1 - ra = 0.28 (foot at x = 0.632, on the flank).
  PrimResult h = oracle_round_cone(kCone, ray({0.8L, -10, -1}, {0, 1, 0}));
  EXPECT_FALSE(h.hit);
  EXPECT_NEAR(double(h.clearance), 0.28, 1e-7);
  EXPECT_NEAR(double(h.t_near), 10.0, 1e-12);
  // Past the tip along the axis, the segment ending at x = 3: the gap to ball b.
  PrimResult e = oracle_round_cone(kCone, ray({5, 0, 0}, {-1, 0, 0}, 0, 2));
  EXPECT_FALSE(e.hit);
  EXPECT_NEAR(double(e.clearance), 2 - 0.4, 1e-7);
  EXPECT_NEAR(double(e.t_near), 2.0, 0);
}

TEST(OracleRoundCone, EqualRadiiMatchCapsule) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<float> u(-1, 1);
  int hits = 0;
  for (int i = 0; i < 2000; ++i) {
    glm::vec3 a(u(rng), u(rng), u(rng)), b(u(rng), u(rng), u(rng));
    float r = 0.05f + 0.3f * std::abs(u(rng));
    PrimRay ry = aimed_ray(rng, glm::mix(a, b, 0.5f + 0.7f * u(rng)), r);
    PrimResult c = oracle_capsule({a, b, r}, ry), k = oracle_round_cone({a, r, b, r}, ry);
    if (c.clearance < 1e-9L) continue;
    ASSERT_EQ(c.hit, k.hit) << i;
    if (!c.hit) continue;
    ++hits;
    EXPECT_NEAR(double(k.t), double(c.t), 1e-13 * double(c.t)) << i;
    EXPECT_NEAR(double(dotl(k.normal, c.normal)), 1.0, 1e-12) << i;
    EXPECT_NEAR(double(k.clearance), double(c.clearance), 1e-9) << i;
  }
  EXPECT_GT(hits, 500);
}

TEST(OracleRoundCone, InvalidAndZeroRadiiMiss) {
  EXPECT_FALSE(oracle_round_cone({{0, 0, 0}, 0.0f, {1, 0, 0}, 0.0f}, ray({0.5L, 0, -5}, {0, 0, 1})).hit);
  EXPECT_FALSE(oracle_round_cone({{0, 0, 0}, -1.0f, {1, 0, 0}, -1.0f}, ray({0.5L, 0, -5}, {0, 0, 1})).hit);
  EXPECT_FALSE(oracle_round_cone(kCone, ray({0.5L, 0, -5}, {0, 0, std::numeric_limits<ld>::quiet_NaN()})).hit);
  // One radius zero: a cone with a point tip at b.
  PrimResult tip = oracle_round_cone({{0, 0, 0}, 0.5f, {2, 0, 0}, 0.0f}, ray({3, 0, 0}, {-1, 0, 0}));
  ASSERT_TRUE(tip.hit);
  EXPECT_NEAR(double(tip.t), 1.0, 1e-15);
}

// The round cone equals the union over s of the balls (a + s (b - a), ra + s (rb - ra)):
// sample 20000 of them, an independent discretisation of the tangent-cone construction.
TEST(OracleRoundCone, MatchesUnionOfInterpolatedBalls) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<float> u(-1, 1);
  int compared = 0;
  for (int prim = 0; prim < 6; ++prim) {
    glm::vec3 a(u(rng), u(rng), u(rng)), b(u(rng), u(rng), u(rng));
    float ra = 0.05f + 0.4f * std::abs(u(rng)), rb = 0.05f + 0.4f * std::abs(u(rng));
    RoundConePrim cone{a, ra, b, rb};
    const int n = 20000;
    std::vector<Vld> cs(n);
    std::vector<ld> rs(n);
    for (int k = 0; k < n; ++k) {
      ld s = ld(k) / (n - 1);
      cs[k] = {a.x + s * (ld(b.x) - a.x), a.y + s * (ld(b.y) - a.y), a.z + s * (ld(b.z) - a.z)};
      rs[k] = ra + s * (ld(rb) - ra);
    }
    for (int i = 0; i < 60; ++i) {
      PrimRay ry = aimed_ray(rng, glm::mix(a, b, 0.5f + 0.8f * u(rng)), std::max(ra, rb));
      PrimResult o = oracle_round_cone(cone, ry);
      UnionHit s = ball_union_entry(cs, rs, ry);
      if (o.clearance < 1e-3L) continue;
      ++compared;
      ASSERT_EQ(o.hit, s.t < kInf) << prim << " " << i;
      if (!o.hit) continue;
      ld dl = std::sqrt(dotl(ry.d, ry.d));
      EXPECT_GE(double(s.t), double(o.t - 1e-12L)) << prim << " " << i;
      EXPECT_LT(double((s.t - o.t) * dl), 1e-4 * std::max(ra, rb)) << prim << " " << i;
      ld nl = std::sqrt(dotl(s.n, s.n));
      EXPECT_GT(double(dotl(s.n, o.normal) / nl), 0.9999) << prim << " " << i;
    }
  }
  EXPECT_GT(compared, 250);
}

// ---------------------------------------------------------------- triangle

TEST(OracleTriangle, HitBarycentricsWindow) {
  glm::vec3 v0(0, 0, 0), v1(1, 0, 0), v2(0, 1, 0);
  PrimResult h = oracle_triangle(v0, v1, v2, ray({0.25L, 0.5L, -2}, {0, 0, 2}));
  ASSERT_TRUE(h.hit);
  EXPECT_DOUBLE_EQ(double(h.t), 1.0);
  EXPECT_DOUBLE_EQ(double(h.u), 0.25);
  EXPECT_DOUBLE_EQ(double(h.v), 0.5);
  expect_normal(h, {0, 0, 1});
  EXPECT_DOUBLE_EQ(double(h.clearance), 0.25);
  EXPECT_FALSE(oracle_triangle(v0, v1, v2, ray({0.75L, 0.5L, -2}, {0, 0, 1})).hit);
  // Starting on the triangle: inside the self window.
  EXPECT_FALSE(oracle_triangle(v0, v1, v2, ray({0.25L, 0.25L, 0}, {0, 0, 1})).hit);
  EXPECT_FALSE(oracle_triangle(v0, v1, v2, ray({0.25L, 0.25L, -1}, {0, 0, 0})).hit);
}
