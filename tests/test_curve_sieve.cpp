// The roving intersector's sieve (kernels/curve_roving.h, step 0): a piece it drops must
// hold no ball that meets the ray at or after z_lo, checked against the curve evaluated
// in long double (an independent Bernstein sum, densely sampled); and the cpu's eight
// lanes (kernels/curve_sieve_simd_cpp.h) must give the one-source loop's verdicts bit
// for bit, on hair-like, folded, degenerate, far and NaN curves.
#include "kernels/intersect_curve.h"
#include <gtest/gtest.h>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>

using namespace masq::kernel;
namespace k = masq::kernel::v_default;

namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

struct SieveCase {
  k::CurveFrame f;
  float r;
  float zlo;
};

// A curve in the ray frame (the ray is the z axis) at scale s, passing the axis at about
// `miss` radii: hair-like (a bent line) most of the time, else wild control points, a
// fold (p1 and p2 swapped past each other), coincident points.
SieveCase random_case(std::mt19937& rng) {
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  std::uniform_real_distribution<float> u01(0.0f, 1.0f);
  const float scales[] = {1e-3f, 1.0f, 1e3f};
  float s = scales[rng() % 3];
  float r = s * (rng() % 2 == 0 ? 1e-3f : 0.05f) * (0.5f + u01(rng));
  glm::vec3 p[4];
  glm::vec3 a(s * u(rng), s * u(rng), s * u(rng));
  glm::vec3 dir = glm::normalize(glm::vec3(u(rng), u(rng), u(rng)) + glm::vec3(1e-3f));
  int kind = int(rng() % 8);
  for (int i = 0; i < 4; ++i) {
    glm::vec3 bend(u(rng), u(rng), u(rng));
    p[i] = a + dir * (s * 2.0f * float(i) / 3.0f) + bend * (kind == 0 ? s : 0.1f * s);
  }
  if (kind == 1) std::swap(p[1], p[2]); // a loop / fold
  if (kind == 2) p[1] = p[0];           // a zero-speed end
  if (kind == 3) p[2] = p[3] = p[1];
  // Move the curve so a random point of it passes the z axis at about miss * r.
  float t = u01(rng), w = 1.0f - t;
  glm::vec3 c = (w * w * w) * p[0] + (3.0f * t * w * w) * p[1] + (3.0f * t * t * w) * p[2] + (t * t * t) * p[3];
  float miss = 2.5f * u01(rng), ang = 6.2831853f * u01(rng);
  glm::vec3 shift(miss * r * std::cos(ang) - c.x, miss * r * std::sin(ang) - c.y, 0.0f);
  SieveCase sc{};
  sc.f.b0 = p[0] + shift;
  sc.f.b1 = p[1] + shift;
  sc.f.b2 = p[2] + shift;
  sc.f.b3 = p[3] + shift;
  sc.f.r = r;
  sc.r = r;
  // z_lo: anywhere along the curve, or (most often) within a few radii of where the ray
  // passes it, where a piece's last ball on the ray decides.
  int where = int(rng() % 6);
  sc.zlo = where == 0 ? -kInf : (where == 1 ? c.z + 3.0f * s * u(rng) : c.z + 2.0f * r * u(rng));
  if (rng() % 500 == 0) sc.f.b1.x = std::numeric_limits<float>::quiet_NaN();
  return sc;
}

// Whether some ball of the piece [s0, s1] of the curve (long double, `samples` points)
// meets the z axis at or after zlo by more than eps: its centre within r - eps of the
// axis and its far crossing at or after zlo + eps.
bool piece_reaches(const k::CurveFrame& f, long double r, long double zlo, long double s0, long double s1,
                   long double eps, int samples) {
  const glm::vec3 b[4] = {f.b0, f.b1, f.b2, f.b3};
  for (int i = 0; i <= samples; ++i) {
    long double t = s0 + (s1 - s0) * i / samples, w = 1.0L - t;
    long double wt[4] = {w * w * w, 3 * t * w * w, 3 * t * t * w, t * t * t};
    long double x = 0, y = 0, z = 0;
    for (int j = 0; j < 4; ++j) {
      x += wt[j] * b[j].x;
      y += wt[j] * b[j].y;
      z += wt[j] * b[j].z;
    }
    long double h2 = x * x + y * y, re = r - eps;
    if (re > 0 && h2 <= re * re && z + std::sqrt(r * r - h2) >= zlo + eps) return true;
  }
  return false;
}

} // namespace

TEST(CurveSieve, DroppedPiecesHoldNoBallThatMeetsTheRayBeyondZlo) {
  std::mt19937 rng(20261205);
  int dropped = 0, kept = 0, wrong = 0;
  for (int n = 0; n < 20000; ++n) {
    SieveCase sc = random_case(rng);
    if (!(sc.f.b1.x == sc.f.b1.x)) continue; // (NaN: the lanes test below)
    // pad 0: the sieve's allowance alone; the intersector adds the frame's rounding.
    unsigned m = k::curve_sieve_kept(sc.f, sc.r, sc.zlo);
    float scale = std::max({std::fabs(sc.f.b0.x), std::fabs(sc.f.b0.y), std::fabs(sc.f.b0.z), std::fabs(sc.f.b3.x),
                            std::fabs(sc.f.b3.y), std::fabs(sc.f.b3.z), sc.r});
    long double eps = 1e-4L * sc.r + 64.0L * 5.96e-8L * scale; // beyond the sieve's own rounding
    for (int p = 0; p < 8; ++p) {
      if (m & (1u << p)) {
        ++kept;
        continue;
      }
      ++dropped;
      if (piece_reaches(sc.f, sc.r, sc.zlo, p / 8.0L, (p + 1) / 8.0L, eps, 400)) {
        if (++wrong <= 5)
          std::printf("case %d piece %d dropped, yet a ball meets the ray beyond zlo = %g (r %g)\n", n, p, sc.zlo, sc.r);
      }
    }
  }
  std::printf("sieve: %d pieces kept, %d dropped, %d dropped wrongly\n", kept, dropped, wrong);
  EXPECT_GT(dropped, 10000); // the cases exercise both verdicts
  EXPECT_GT(kept, 10000);
  EXPECT_EQ(wrong, 0);
}

TEST(CurveSieve, EightLanesGiveTheOneSourceLoopsVerdicts) {
  std::mt19937 rng(7);
  int differ = 0;
  for (int n = 0; n < 200000; ++n) {
    SieveCase sc = random_case(rng);
    float pad = rng() % 2 == 0 ? 0.0f : 1e-5f * sc.r;
    float rr = (sc.r + pad) + pad;
    const glm::vec3 b[4] = {sc.f.b0, sc.f.b1, sc.f.b2, sc.f.b3};
    unsigned lanes = simd::curve_sieve_mask8(b, rr, sc.zlo);
    unsigned loop = k::curve_sieve_kept(sc.f, rr, sc.zlo);
    if (lanes != loop && ++differ <= 5) std::printf("case %d: lanes %02x, loop %02x\n", n, lanes, loop);
  }
  EXPECT_EQ(differ, 0);
}
