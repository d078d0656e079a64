// The cpu dialect's four-lane triangle test (kernels/triangle_simd_cpp.h) against the
// one-source intersect_triangle: every lane's hit flag, t, barycentrics and normal must be
// bit-identical to the scalar call's, for ordinary, slivered, degenerate (collinear,
// zero-area) and invalid (NaN) triangles, rays through their edges and vertices, rays
// leaving their surface (the self-intersection window and the plane rule) and intervals
// that cut crossings off. Then whole leaves through intersect_leaf, which takes the lanes
// in reference order with the scalar call's scaled comparison, against the loop it
// replaces, closest and any hit, on mesh patches whose triangles share edges (rays
// through an edge meet two triangles at nearly the same t) and repeat (exact ties).
#include "kernels/traverse.h"
#include <gtest/gtest.h>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <string>
#include <vector>

using namespace masq::kernel;
namespace k = masq::kernel::v_default;

namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();
std::uint32_t bits(float x) { return std::bit_cast<std::uint32_t>(x); }

Triangle make_triangle(glm::vec3 a, glm::vec3 b, glm::vec3 c) {
  Triangle t{};
  for (int i = 0; i < 3; ++i) {
    t.v0[i] = a[i];
    t.v1[i] = b[i];
    t.v2[i] = c[i];
  }
  return t;
}
glm::vec3 vertex(const Triangle& t, int k) {
  const float* v = k == 0 ? t.v0 : (k == 1 ? t.v1 : t.v2);
  return {v[0], v[1], v[2]};
}

// A triangle at scale s near `at`: random edges from s/1000 to 2s, now and then a sliver,
// collinear or zero-area one, or a NaN vertex.
Triangle random_triangle(std::mt19937& rng, glm::vec3 at, float s) {
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  auto edge = [&]() {
    float len = s * std::exp2(u(rng) * 5.0f - 4.0f);
    return len * glm::normalize(glm::vec3(u(rng), u(rng), u(rng)) + glm::vec3(1e-3f));
  };
  glm::vec3 a = at + s * glm::vec3(u(rng), u(rng), u(rng));
  glm::vec3 e1 = edge(), e2 = edge();
  int odd = int(rng() % 40);
  if (odd == 0) e2 = 2.0f * e1;                    // collinear
  if (odd == 1) e1 = e2 = glm::vec3(0.0f);        // a point
  if (odd == 2) e2 = e1 + 1e-6f * edge();          // a sliver
  Triangle t = make_triangle(a, a + e1, a + e2);
  if (odd == 3) t.v1[rng() % 3] = std::nanf("");
  return t;
}

struct Probe {
  glm::vec3 o, d;
  float tmin, tmax;
};

// Rays at a triangle: through a barycentric point near it (edges and vertices included)
// from far or near, or from a point on it (secondary rays), unit or scaled directions,
// full or cut intervals.
Probe random_probe(std::mt19937& rng, const Triangle& t, float s) {
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  glm::vec3 a = vertex(t, 0), b = vertex(t, 1), c = vertex(t, 2);
  float bu = 0.7f * (u(rng) + 1.0f) - 0.2f, bv = 0.7f * (u(rng) + 1.0f) - 0.2f;
  int kind = int(rng() % 6);
  if (kind == 0) bv = 0.0f;               // on the edge v0 v1
  if (kind == 1) bv = 1.0f - bu;          // on the edge v1 v2
  if (kind == 2) bu = bv = 0.0f;          // the vertex v0
  glm::vec3 aim = a + bu * (b - a) + bv * (c - a);
  glm::vec3 dir = glm::normalize(glm::vec3(u(rng), u(rng), u(rng)) + glm::vec3(1e-3f));
  Probe p;
  if (kind == 5) {
    p.o = aim; // leaving the surface
    p.d = dir;
  } else {
    float dist = s * std::exp2(u(rng) * 8.0f);
    p.o = aim - dist * dir;
    p.d = dir;
  }
  p.d = p.d * std::exp2(float(int(rng() % 9)) - 4.0f);
  p.tmin = rng() % 4 == 0 ? 1e-3f * u(rng) * u(rng) : 0.0f;
  p.tmax = kInf;
  if (rng() % 4 == 0) p.tmax = std::fabs(u(rng)) * 2.0f * s * std::exp2(u(rng) * 8.0f);
  if (rng() % 50 == 0) p.d = glm::vec3(0.0f);
  if (rng() % 50 == 0) p.o.x = std::nanf("");
  return p;
}

TEST(TriangleSimd, EveryLaneMatchesTheScalarIntersectorBitForBit) {
  std::mt19937 rng(21);
  long hits = 0, surface_rays = 0, mismatches = 0;
  std::string first;
  for (int c = 0; c < 60000; ++c) {
    float s = std::exp2(float(int(rng() % 13)) - 6.0f);
    glm::vec3 at = (rng() % 3 == 0) ? glm::vec3(1000.0f * s) : glm::vec3(0.0f);
    int n = 1 + int(rng() % 4);
    Triangle tris[4];
    int refs[4] = {0, 1, 2, 3};
    for (int i = 0; i < n; ++i) tris[i] = random_triangle(rng, at, s);
    Probe p = random_probe(rng, tris[rng() % unsigned(n)], s);
    surface_rays += p.tmax == kInf && p.tmin == 0.0f;
    simd::TriangleHits4 got = simd::triangle_hits4(simd::triangle_lanes4(tris, 0, refs, n), simd::lanes_below(n), p.o,
                                                   p.d, p.tmin, p.tmax);
    for (int i = 0; i < n; ++i) {
      k::PrimHit want = k::intersect_triangle(tris[i], p.o, p.d, p.tmin, p.tmax);
      bool same = got.hit[i] == want.hit;
      if (same && want.hit)
        same = bits(got.t[i]) == bits(want.t) && bits(got.u[i]) == bits(want.u) && bits(got.v[i]) == bits(want.v) &&
               bits(got.nx[i]) == bits(want.normal.x) && bits(got.ny[i]) == bits(want.normal.y) &&
               bits(got.nz[i]) == bits(want.normal.z);
      hits += want.hit;
      if (!same && mismatches++ == 0)
        first = "case " + std::to_string(c) + " lane " + std::to_string(i) + ": hit " + std::to_string(got.hit[i]) +
                " t " + std::to_string(got.t[i]) + " vs hit " + std::to_string(want.hit) + " t " +
                std::to_string(want.t);
    }
  }
  EXPECT_EQ(mismatches, 0) << first;
  EXPECT_GT(hits, 8000);
  EXPECT_GT(surface_rays, 1000);
}

// A patch of a mesh: a grid of quads, two triangles each, sharing edges and vertices,
// slightly bumpy, as a BVH leaf of a real mesh holds them.
std::vector<Triangle> mesh_patch(std::mt19937& rng, float s) {
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  glm::vec3 p[3][3];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) p[i][j] = s * glm::vec3(float(i), 0.1f * u(rng), float(j));
  std::vector<Triangle> t;
  for (int i = 0; i < 2; ++i)
    for (int j = 0; j < 2; ++j) {
      t.push_back(make_triangle(p[i][j], p[i + 1][j], p[i + 1][j + 1]));
      t.push_back(make_triangle(p[i][j], p[i + 1][j + 1], p[i][j + 1]));
    }
  return t;
}

// Leaves of 1..9 triangles (refs drawn with repeats from a mesh patch: shared edges and
// exact ties) through intersect_leaf against the one-source loop over the same refs.
TEST(TriangleSimd, LeavesGiveTheLoopsNearestAndFirstHit) {
  std::mt19937 rng(22);
  long hits = 0, mismatches = 0;
  std::string first;
  for (int any = 0; any < 2; ++any) {
    k::MASQ_ANY_HIT = any != 0;
    for (int c = 0; c < 20000; ++c) {
      float s = std::exp2(float(int(rng() % 9)) - 4.0f);
      std::vector<Triangle> tris = mesh_patch(rng, s);
      int n = 1 + int(rng() % 9);
      std::vector<int> refs(static_cast<std::size_t>(n));
      for (int j = 0; j < n; ++j) refs[std::size_t(j)] = int(rng() % tris.size());
      KernelData kd{};
      kd.triangles = tris.data();
      kd.refs = refs.data();
      Geometry g{MASQ_PRIM_TRIANGLE, 0, int(tris.size()), 0};
      Probe p = random_probe(rng, tris[std::size_t(refs[0])], s);
      if (rng() % 3 == 0) { // through a shared vertex or edge midpoint of the grid
        glm::vec3 aim = s * glm::vec3(float(rng() % 5) * 0.5f, 0.0f, float(rng() % 5) * 0.5f);
        aim.y = vertex(tris[0], 0).y;
        p.d = glm::normalize(glm::vec3(0.3f * float(int(rng() % 3) - 1), -1.0f, 0.2f));
        p.o = aim - 3.0f * s * p.d;
      }
      k::Nearest start = k::nearest_none(p.tmax);
      k::LeafOut got = k::intersect_leaf(kd, g, 0, n, 2, 3, p.o, p.d, p.tmin, start);
      k::Nearest want = start;
      for (int j = 0; j < n; ++j) {
        int prim = refs[std::size_t(j)];
        k::PrimHit ph = k::intersect_triangle(tris[std::size_t(prim)], p.o, p.d, p.tmin, want.t);
        want = k::nearest_take(want, ph, prim, 2, 3);
        if (any && want.prim >= 0) break;
      }
      bool same = got.nearest.prim == want.prim && bits(got.nearest.t) == bits(want.t) &&
                  got.nearest.geom == want.geom && got.nearest.inst == want.inst &&
                  bits(got.nearest.normal.x) == bits(want.normal.x) && bits(got.nearest.normal.y) == bits(want.normal.y) &&
                  bits(got.nearest.u) == bits(want.u) && bits(got.nearest.v) == bits(want.v);
      hits += want.prim >= 0;
      if (!same && mismatches++ == 0)
        first = "leaf of " + std::to_string(n) + (any ? " (any hit)" : "") + ": prim " +
                std::to_string(got.nearest.prim) + " t " + std::to_string(got.nearest.t) + " vs prim " +
                std::to_string(want.prim) + " t " + std::to_string(want.t);
    }
  }
  k::MASQ_ANY_HIT = false;
  EXPECT_EQ(mismatches, 0) << first;
  EXPECT_GT(hits, 40000 / 5);
}

} // namespace
