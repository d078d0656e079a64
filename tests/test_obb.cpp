// The masquerade transform, as stored in fp32, maps each capsule inside the unit box
// (checked in double on surface samples) and is tight (the capsule reaches the faces).
#include "bvh/bounds/obb.h"
#include <gtest/gtest.h>
#include <random>
#include "tests/random_affine.h"

using namespace masq;
using masq::test::random_affine;

TEST(Obb, CapsuleMapsInsideUnitBoxAndTouchesIt) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int trial = 0; trial < 500; ++trial) {
    CapsulePrim c{glm::vec3(u(rng), u(rng), u(rng)) * 100.0f, glm::vec3(u(rng), u(rng), u(rng)) * 100.0f,
                  float(std::pow(10.0, -4.0 + 4.0 * std::abs(u(rng))))};
    if (trial % 7 == 0) c.b = c.a; // zero length: a sphere
    Affine3 xf = trial % 2 ? random_affine(rng, 1000.0, 0.5, 3.0) : Affine3{};
    MasqueradeBox mb = capsule_masquerade_box(c, xf);
    Affine3 stored = from_mat3x4f(mb.world_to_unit);
    double reach = 0.0;
    // Surface samples: points on spheres around the endpoints and the axis.
    for (int k = 0; k < 200; ++k) {
      glm::dvec3 dir = glm::normalize(glm::dvec3(u(rng), u(rng), u(rng)));
      double s = (k % 3) / 2.0;
      glm::dvec3 p = glm::mix(glm::dvec3(c.a), glm::dvec3(c.b), s) + double(c.radius) * dir;
      glm::dvec3 q = stored.apply_point(xf.apply_point(p));
      double m = std::max({std::abs(q.x), std::abs(q.y), std::abs(q.z)});
      ASSERT_LE(m, 1.0) << "trial " << trial;
    }
    // Tightness, exactly: the capsule's support along each unit axis (endpoints plus
    // r * |row| of the composed linear map) must reach the faces.
    glm::dmat3 g = stored.linear * xf.linear;
    glm::dvec3 off = stored.linear * xf.translation + stored.translation;
    for (int k = 0; k < 3; ++k) {
      glm::dvec3 row(g[0][k], g[1][k], g[2][k]);
      for (glm::dvec3 p : {glm::dvec3(c.a), glm::dvec3(c.b)})
        reach = std::max(reach, std::abs(glm::dot(row, p) + off[k]) + double(c.radius) * glm::length(row));
    }
    EXPECT_LE(reach, 1.0) << "trial " << trial;
    // Slack allowed: the fp32 rounding of the stored map, which grows with the size of
    // the translation in unit-box units (a far-away thin capsule has |b| >> 1).
    double magnitude = 1.0;
    for (int k = 0; k < 3; ++k) magnitude = std::max(magnitude, std::abs(off[k]) + glm::length(glm::dvec3(g[0][k], g[1][k], g[2][k])) * 200.0);
    EXPECT_GT(reach, 1.0 - 32 * 5.96e-8 * magnitude) << "OBB not tight, trial " << trial;
  }
}

TEST(Obb, ZeroRadiusHasNoBox) {
  EXPECT_THROW(capsule_masquerade_box({{0, 0, 0}, {1, 0, 0}, 0.0f}, {}), std::runtime_error);
}

namespace {
// Points of the primitive's surface (cone: points of its end balls and of the hull
// between them; curve: balls around points of the curve itself).
std::vector<glm::dvec3> surface_samples(const Geometry& g, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0), s01(0.0, 1.0);
  std::vector<glm::dvec3> pts;
  for (int k = 0; k < 300; ++k) {
    glm::dvec3 dir = glm::normalize(glm::dvec3(u(rng), u(rng), u(rng)));
    double s = s01(rng);
    switch (g.type) {
      case PrimType::RoundCone: {
        const RoundConePrim& c = g.round_cones[0];
        glm::dvec3 p = glm::mix(glm::dvec3(c.a), glm::dvec3(c.b), s);
        pts.push_back(p + glm::mix(double(c.ra), double(c.rb), s) * dir); // inside the hull
        pts.push_back(glm::dvec3(k % 2 ? c.a : c.b) + double(k % 2 ? c.ra : c.rb) * dir);
        break;
      }
      case PrimType::Sphere: pts.push_back(glm::dvec3(g.spheres[0].center) + double(g.spheres[0].radius) * dir); break;
      case PrimType::Curve: {
        const CurvePrim& c = g.curves[0];
        double t = 1 - s;
        glm::dvec3 p = t * t * t * glm::dvec3(c.p[0]) + 3 * t * t * s * glm::dvec3(c.p[1]) +
                       3 * t * s * s * glm::dvec3(c.p[2]) + s * s * s * glm::dvec3(c.p[3]);
        pts.push_back(p + double(c.radius) * dir);
        break;
      }
      default: break;
    }
  }
  return pts;
}
} // namespace

TEST(Obb, EveryThinPrimitiveMapsInsideUnitBox) {
  // Round cones (with contained balls), spheres and curves (both OBB fits), under
  // random rotations, non-uniform scales and translations up to 1e3.
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  double tight_area = 0, paper_area = 0;
  for (int trial = 0; trial < 600; ++trial) {
    Geometry g;
    float r = float(std::pow(10.0, -4.0 + 3.0 * std::abs(u(rng))));
    glm::vec3 a = glm::vec3(u(rng), u(rng), u(rng)) * 10.0f, b = a + glm::vec3(u(rng), u(rng), u(rng)) * 2.0f;
    switch (trial % 3) {
      case 0:
        g.type = PrimType::RoundCone;
        g.round_cones.push_back({a, r, trial % 9 == 0 ? a + glm::vec3(0.3f * r, 0, 0) : b, 0.4f * r});
        break;
      case 1:
        g.type = PrimType::Sphere;
        g.spheres.push_back({a, r});
        break;
      default: {
        g.type = PrimType::Curve;
        CurvePrim c{};
        c.p = {a, a + glm::vec3(u(rng), u(rng), u(rng)), b + glm::vec3(u(rng), u(rng), u(rng)), b};
        if (trial % 11 == 2) c.p = {a, a, a, a}; // coincident control points
        c.radius = r;
        g.curves.push_back(c);
      }
    }
    Affine3 xf = trial % 2 ? random_affine(rng, 1000.0, 0.5, 3.0) : Affine3{};
    for (CurveObb mode : {CurveObb::Tight, CurveObb::Paper}) {
      MasqueradeBox mb = masquerade_box(g, 0, xf, mode);
      Affine3 stored = from_mat3x4f(mb.world_to_unit);
      for (const glm::dvec3& p : surface_samples(g, rng)) {
        glm::dvec3 q = stored.apply_point(xf.apply_point(p));
        ASSERT_LE(std::max({std::abs(q.x), std::abs(q.y), std::abs(q.z)}), 1.0)
            << prim_type_name(g.type) << " " << curve_obb_name(mode) << " trial " << trial;
      }
      if (g.type == PrimType::Curve) (mode == CurveObb::Tight ? tight_area : paper_area) += mb.obb_area;
      if (g.type != PrimType::Curve) break; // one fit for the others
    }
  }
  std::printf("curve OBB surface area: tight / paper = %.3f\n", tight_area / paper_area);
  EXPECT_LT(tight_area, paper_area); // the tighter fit must be tighter in total
}

// A piece of a subdivided TressFX strand (tressfx3_bear.tfx, curve 253488 after x2
// pre-splitting): its control points are collinear up to fp32 rounding, 1e-4 radii
// apart. The noise offset is not perpendicular to the chord; using it as an axis gave a
// singular frame and a NaN box that crashed the TLAS build.
TEST(Obb, NearlyCollinearShortCurveHasAFiniteBox) {
  for (CurveObb mode : {CurveObb::Tight, CurveObb::Paper}) {
    Geometry g;
    g.type = PrimType::Curve;
    g.curves.push_back({{glm::vec3(-8.14569664f, 71.6065674f, -143.01799f), glm::vec3(-8.14569473f, 71.6065598f, -143.01799f),
                         glm::vec3(-8.14569092f, 71.6065445f, -143.01799f), glm::vec3(-8.1456871f, 71.6065292f, -143.01799f)},
                        0.245165f});
    MasqueradeBox b = masquerade_box(g, 0, Affine3{}, mode);
    for (int k = 0; k < 3; ++k) {
      EXPECT_TRUE(std::isfinite(b.world_box.lo[k]) && std::isfinite(b.world_box.hi[k])) << curve_obb_name(mode);
      EXPECT_GT(b.world_box.hi[k] - b.world_box.lo[k], 0.49) << curve_obb_name(mode); // at least the ball's diameter
    }
    for (float v : b.world_to_unit) EXPECT_TRUE(std::isfinite(v)) << curve_obb_name(mode);
  }
}
