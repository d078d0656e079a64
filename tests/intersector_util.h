// What the per-intersector tests (test_intersectors_*.cpp, test_curve_intersector_*.cpp)
// share: long-double vector arithmetic of their own (not the oracle's, so an error there
// cannot cancel in both), random sampling, fp32 rays with their long-double twins, the
// constants of the band within which fp32 may legitimately flip hit and miss (the
// band itself is explained where each test file compares), and the tally of rays that
// start on a surface.
#pragma once
#include "oracle/oracle_prims.h"
#include <glm/glm.hpp>
#include <gtest/gtest.h>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <utility>

namespace masq::test {

using masq::oracle::ld;
using masq::oracle::PrimRay;
using masq::oracle::PrimResult;
using masq::oracle::Vld;
using Rng = std::mt19937_64;

inline constexpr ld kU = 1.0L / 16777216; // 2^-24
inline constexpr ld kBand = 4;
inline constexpr ld kBandFloor = 1e-4L;
inline constexpr ld kTolRel = 1e-3L;
inline const float kInfF = std::numeric_limits<float>::infinity();

inline Vld operator+(Vld a, Vld b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
inline Vld operator-(Vld a, Vld b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
inline Vld operator*(ld s, Vld a) { return {s * a.x, s * a.y, s * a.z}; }
inline ld dotl(Vld a, Vld b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline Vld crossl(Vld a, Vld b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
inline ld lenl(Vld a) { return std::sqrt(dotl(a, a)); }
inline Vld unitl(Vld a) { return (1 / lenl(a)) * a; }
inline Vld to_ld(glm::vec3 v) { return {v.x, v.y, v.z}; }
inline glm::vec3 to_f(Vld v) { return {float(v.x), float(v.y), float(v.z)}; }

inline ld uni(Rng& g, ld lo, ld hi) { return lo + (hi - lo) * std::uniform_real_distribution<double>(0, 1)(g); }
inline ld log_uni(Rng& g, ld lo, ld hi) { return std::exp(uni(g, std::log(lo), std::log(hi))); }
inline Vld rand_unit(Rng& g) {
  std::normal_distribution<double> n(0, 1);
  Vld v{n(g), n(g), n(g)};
  return unitl(v);
}
inline Vld rand_perp(Rng& g, Vld n) { return unitl(crossl(n, rand_unit(g))); }

inline PrimRay ld_ray(glm::vec3 o, glm::vec3 d, float tmin = 0, float tmax = kInfF) {
  return {to_ld(o), to_ld(d), ld(tmin), ld(tmax)};
}

// A ray from the fp32 origin o towards aim, with a random non-unit length of d
// (computed from the rounded origin, so the ray really passes through aim).
inline std::pair<glm::vec3, glm::vec3> aimed_ray(Vld o, Vld aim, Rng& rng) {
  glm::vec3 of = to_f(o);
  Vld dir = aim - to_ld(of);
  ld scale = log_uni(rng, 1e-2, 1e2) / lenl(dir);
  return {of, to_f(scale * dir)};
}

// A ray from a surface point rounded to fp32 starts on a crossing at tcross (signed
// distance of the rounded origin from the exact tangent plane over d.n), which the
// kernel places within about e_t. Held: well inside the self window, the kernel must
// ignore it. Off: well outside (the rounding moved the origin further than the window
// reaches; the window scales with r and |o - c|, not with |o|), the kernel must agree
// with the oracle, which sees the same rounded origin. Between: too close to call.
struct StartTally {
  long rays = 0, held = 0, held_hits = 0, off = 0, off_flips = 0;
  void add(ld tcross, ld tself, ld e_t, bool kernel_hit, bool oracle_hit) {
    ++rays;
    if (std::fabs(tcross) + e_t < 0.5L * tself) {
      ++held;
      held_hits += kernel_hit;
    } else if (std::fabs(tcross) > 2 * (tself + e_t)) {
      ++off;
      off_flips += kernel_hit != oracle_hit;
    }
  }
  void report(const char* what) const {
    std::printf("%s: %ld rays; %ld start well inside the window (robust hits on them: %ld); %ld start beyond it "
                "(robust disagrees with the oracle on %ld); %ld at its edge\n",
                what, rays, held, held_hits, off, off_flips, rays - held - off);
  }
  void check(const char* what) const {
    report(what);
    EXPECT_GT(held, rays / 2) << what << ": the test must mostly make rays that start on the surface";
    EXPECT_EQ(held_hits, 0) << what << ": self hits";
    EXPECT_EQ(off_flips, 0) << what;
  }
};

} // namespace masq::test
