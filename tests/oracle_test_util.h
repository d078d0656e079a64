// What the oracle's own tests (test_oracle_*.cpp) share: long-double rays and the few
// vector operations they need (written apart from the oracle's), the entry into and
// exit from a union of balls (an independent discretisation of the swept-sphere and
// round-cone solids), random rays aimed near a point, and straight test curves.
#pragma once
#include "oracle/oracle_prims.h"
#include <gtest/gtest.h>
#include <glm/glm.hpp>
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <random>
#include <utility>
#include <vector>

namespace masq::test {

using masq::oracle::ld;
using masq::oracle::PrimRay;
using masq::oracle::PrimResult;
using masq::oracle::Vld;

inline const ld kInf = std::numeric_limits<ld>::infinity();

inline PrimRay ray(Vld o, Vld d, ld tmin = 0, ld tmax = kInf) { return {o, d, tmin, tmax}; }

inline void expect_normal(const PrimResult& h, Vld n, ld tol = 1e-15L) {
  EXPECT_NEAR(double(h.normal.x), double(n.x), double(tol));
  EXPECT_NEAR(double(h.normal.y), double(n.y), double(tol));
  EXPECT_NEAR(double(h.normal.z), double(n.z), double(tol));
}

inline Vld v(const glm::vec3& p) { return {p.x, p.y, p.z}; }
inline Vld sub(Vld a, Vld b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
inline ld dotl(Vld a, Vld b) { return a.x * b.x + a.y * b.y + a.z * b.z; }

inline glm::vec3 bezier(const CurvePrim& c, double s) {
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
inline UnionHit ball_union_entry(const std::vector<Vld>& c, const std::vector<ld>& r, const PrimRay& ry) {
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
inline ld ball_union_exit(const std::vector<Vld>& c, const std::vector<ld>& r, const PrimRay& ry) {
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
inline PrimRay aimed_ray(std::mt19937_64& rng, glm::vec3 target, double r) {
  std::normal_distribution<double> g(0.0, 1.0);
  glm::dvec3 dir = glm::normalize(glm::dvec3(g(rng), g(rng), g(rng)));
  glm::dvec3 off(g(rng), g(rng), g(rng));
  glm::dvec3 aim = glm::dvec3(target) + off * (0.9 * r);
  glm::dvec3 o = aim - 5.0 * dir;
  glm::dvec3 d = dir * (0.5 + std::uniform_real_distribution<double>(0, 2)(rng));
  return ray({o.x, o.y, o.z}, {d.x, d.y, d.z});
}

inline CurvePrim straight_curve(glm::vec3 a, glm::vec3 b, float r) {
  // Evenly spaced collinear control points: C(s) = a + s (b - a) exactly (in long double).
  CurvePrim c;
  for (int i = 0; i < 4; ++i) c.p[i] = a + (b - a) * (float(i) / 3.0f);
  c.radius = r;
  return c;
}

} // namespace masq::test
