// The long-double oracle, checked against hand-computed answers per primitive type and
// against brute-force unions of many small balls (an independent discretisation of the
// swept-sphere and round-cone solids).
#include "oracle/oracle.h"
#include "oracle/oracle_prims.h"
#include <gtest/gtest.h>
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <random>

using namespace masq;
using namespace masq::oracle;

namespace {

const ld kInf = std::numeric_limits<ld>::infinity();

PrimRay ray(Vld o, Vld d, ld tmin = 0, ld tmax = kInf) { return {o, d, tmin, tmax}; }

void expect_normal(const PrimResult& h, Vld n, ld tol = 1e-15L) {
  EXPECT_NEAR(double(h.normal.x), double(n.x), double(tol));
  EXPECT_NEAR(double(h.normal.y), double(n.y), double(tol));
  EXPECT_NEAR(double(h.normal.z), double(n.z), double(tol));
}

Vld v(const glm::vec3& p) { return {p.x, p.y, p.z}; }
Vld sub(Vld a, Vld b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
ld dotl(Vld a, Vld b) { return a.x * b.x + a.y * b.y + a.z * b.z; }

glm::vec3 bezier(const CurvePrim& c, double s) {
  double w0 = (1 - s) * (1 - s) * (1 - s), w1 = 3 * s * (1 - s) * (1 - s), w2 = 3 * s * s * (1 - s), w3 = s * s * s;
  return glm::vec3(glm::dvec3(c.p[0]) * w0 + glm::dvec3(c.p[1]) * w1 + glm::dvec3(c.p[2]) * w2 + glm::dvec3(c.p[3]) * w3);
}

// Entry of the ray into the union of the balls (c_k, r_k): min over the balls of the
// entry parameter (rays start outside every ball). Returns inf on a miss.
struct UnionHit {
  ld t = kInf;
  Vld n;
  std::size_t ball = 0;
};
UnionHit ball_union_entry(const std::vector<Vld>& c, const std::vector<ld>& r, const PrimRay& ry) {
  UnionHit best;
  ld dd = dotl(ry.d, ry.d);
  for (std::size_t k = 0; k < c.size(); ++k) {
    Vld oc = sub(ry.o, c[k]);
    ld b = dotl(oc, ry.d), cc = dotl(oc, oc) - r[k] * r[k];
    ld disc = b * b - dd * cc;
    if (disc < 0) continue;
    ld t = (-b - std::sqrt(disc)) / dd;
    if (t < best.t) {
      best.t = t;
      best.n = {oc.x + t * ry.d.x, oc.y + t * ry.d.y, oc.z + t * ry.d.z};
      best.ball = k;
    }
  }
  return best;
}

// First exit of a ray that starts inside the union of the balls: the end of the merged
// run of ball intervals that contains t = 0.
ld ball_union_exit(const std::vector<Vld>& c, const std::vector<ld>& r, const PrimRay& ry) {
  std::vector<std::pair<ld, ld>> iv;
  ld dd = dotl(ry.d, ry.d);
  for (std::size_t k = 0; k < c.size(); ++k) {
    Vld oc = sub(ry.o, c[k]);
    ld b = dotl(oc, ry.d), cc = dotl(oc, oc) - r[k] * r[k];
    ld disc = b * b - dd * cc;
    if (disc >= 0) iv.push_back({(-b - std::sqrt(disc)) / dd, (-b + std::sqrt(disc)) / dd});
  }
  std::sort(iv.begin(), iv.end());
  ld end = -kInf;
  for (const auto& [a, b] : iv) {
    if (a > 0 && a > end) break; // a gap after t = 0 (or before any interval reached 0)
    end = std::max(end, b);
  }
  return end > 0 ? end : -kInf;
}

// A ray from distance ~5 aimed at a point within 1.5 r of `target`.
PrimRay aimed_ray(std::mt19937_64& rng, glm::vec3 target, double r) {
  std::normal_distribution<double> g(0.0, 1.0);
  glm::dvec3 dir = glm::normalize(glm::dvec3(g(rng), g(rng), g(rng)));
  glm::dvec3 off(g(rng), g(rng), g(rng));
  glm::dvec3 aim = glm::dvec3(target) + off * (0.9 * r);
  glm::dvec3 o = aim - 5.0 * dir;
  glm::dvec3 d = dir * (0.5 + std::uniform_real_distribution<double>(0, 2)(rng));
  return ray({o.x, o.y, o.z}, {d.x, d.y, d.z});
}

} // namespace

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

// ---------------------------------------------------------------- curve

CurvePrim straight_curve(glm::vec3 a, glm::vec3 b, float r) {
  // Evenly spaced collinear control points: C(s) = a + s (b - a) exactly (in long double).
  CurvePrim c;
  for (int i = 0; i < 4; ++i) c.p[i] = a + (b - a) * (float(i) / 3.0f);
  c.radius = r;
  return c;
}

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

// ---------------------------------------------------------------- Oracle::trace

TEST(OracleTrace, EveryTypeThroughAnInstance) {
  Scene s;
  s.name = "every type";
  Geometry tri, cap, cone, sph, cur;
  tri.type = PrimType::Triangle;
  tri.vertices = {{-1, -1, 0}, {1, -1, 0}, {0, 1, 0}};
  tri.triangles = {{0, 1, 2}};
  cap.type = PrimType::Capsule;
  cap.capsules = {{{-1, 0, 0}, {1, 0, 0}, 0.25f}};
  cone.type = PrimType::RoundCone;
  cone.cones = {{{0, 0, 0}, 0.5f, {2, 0, 0}, 0.25f}};
  sph.type = PrimType::Sphere;
  sph.spheres = {{{0, 0, 0}, 0.5f}};
  cur.type = PrimType::Curve;
  cur.curves = {straight_curve({-1.5f, 0, 0}, {1.5f, 0, 0}, 0.25f)};
  s.geometries = {tri, cap, cone, sph, cur};
  // Each geometry placed at x = 10 k, scaled by 2 along z, along the ray x = 10 k.
  for (std::uint32_t k = 0; k < 5; ++k) {
    Instance in;
    in.geometry = k;
    in.object_to_world.linear = glm::dmat3(1.0);
    in.object_to_world.linear[2][2] = 2.0;
    in.object_to_world.translation = {10.0 * k, 0.0, 0.0};
    s.instances.push_back(in);
  }
  Oracle o(s);
  auto trace = [&](float x, float tmax = 1e30f) {
    kernel::Ray r{};
    r.org[0] = x;
    r.org[1] = 0;
    r.org[2] = -10;
    r.dir[0] = 0;
    r.dir[1] = 0;
    r.dir[2] = 2;
    r.tmin = 0;
    r.tmax = tmax;
    return o.trace(r);
  };
  // Object-space answers along z, scaled by 2 in world z: hit at world z = 2 z_obj.
  // Triangle plane z = 0; capsule and curve radius 0.25; the cone at its end a is
  // sphere a's cap (x = 0 < ra sin(phi) = 0.0625); sphere radius 0.5.
  const double z_obj[5] = {0.0, -0.25, -0.5, -0.5, -0.25};
  for (int k = 0; k < 5; ++k) {
    OracleHit h = trace(10.0f * k);
    ASSERT_EQ(h.inst, k);
    EXPECT_EQ(h.geom, k);
    EXPECT_EQ(h.prim, 0);
    EXPECT_NEAR(double(h.t), (10.0 + 2.0 * z_obj[k]) / 2.0, 1e-12) << k;
    EXPECT_NEAR(h.normal.z, k == 0 ? 1.0 : -1.0, 1e-12) << k; // triangle: winding normal
    EXPECT_EQ(double(h.second_t), double(kInf));
  }
  EXPECT_LT(trace(5.0f).prim, 0);
  EXPECT_LT(trace(30.0f, 4.0f).prim, 0);
}
