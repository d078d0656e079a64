// Compact masquerade entries (bvh/nodes/compact_instance.h, kernels/masq_instance.h): the
// decoded map keeps every primitive inside the unit box, also under the worst decode
// error the encoder allows for; the kernel's own fp32 decode stays within that bound;
// and the box is hardly looser than the 64-byte instance's.
#include "bvh/nodes/compact_instance.h"
#include "bvh/nodes/compact_fit.h"
#include "bvh/bounds/prim_bounds.h"
#include "kernels/masq_instance.h"
#include <gtest/gtest.h>
#include <bit>
#include <cstdint>
#include <cstdio>
#include <random>
#include "tests/random_affine.h"

using namespace masq;

namespace {

constexpr double kU = 0x1p-24;

struct Case {
  Geometry g;
  Affine3 xf;
};

// A thin primitive of size `scale` (radius 1e-2..1 of it, length up to 20 of it) whose
// centre lies up to `far` sizes from the origin, under a random rotation; one in four
// under an affine scene instance (non-uniform scale: the compact box is then fitted in
// the world, not mapped).
Case random_case(std::mt19937_64& rng, int trial, double far_max) {
  std::uniform_real_distribution<double> u(-1.0, 1.0), u01(0.0, 1.0);
  const double scale = std::pow(10.0, -6.0 + 9.0 * u01(rng));
  const double far = scale * std::pow(10.0, std::log10(far_max) * u01(rng));
  const glm::dvec3 centre = far * glm::normalize(glm::dvec3(u(rng), u(rng), u(rng)));
  const glm::dvec3 axis = glm::normalize(glm::dvec3(u(rng), u(rng), u(rng)));
  const double len = 20.0 * scale * u01(rng);
  const float r = float(scale * std::pow(10.0, -2.0 + 2.0 * u01(rng)));
  const glm::vec3 a(centre - 0.5 * len * axis), b(centre + 0.5 * len * axis);
  Case c;
  switch (trial % 4) {
    case 0:
      c.g.type = PrimType::Capsule;
      c.g.capsules.push_back({a, b, r});
      break;
    case 1:
      c.g.type = PrimType::RoundCone;
      c.g.round_cones.push_back({a, r, b, float(r * (0.2 + 0.8 * u01(rng)))});
      break;
    case 2:
      c.g.type = PrimType::Sphere;
      c.g.spheres.push_back({glm::vec3(centre), r});
      break;
    default: {
      c.g.type = PrimType::Curve;
      CurvePrim cv{};
      glm::dvec3 bend = glm::normalize(glm::cross(axis, glm::dvec3(u(rng), u(rng), u(rng)))) * (len * 0.2 * u01(rng));
      cv.p = {a, glm::vec3(glm::dvec3(a) + (glm::dvec3(b) - glm::dvec3(a)) / 3.0 + bend),
              glm::vec3(glm::dvec3(a) + 2.0 * (glm::dvec3(b) - glm::dvec3(a)) / 3.0 - bend), b};
      cv.radius = r;
      c.g.curves.push_back(cv);
    }
  }
  if (trial % 8 == 5) {
    c.xf = test::random_affine(rng, 0.0, 0.5, 3.0); // rotation and non-uniform scale about the origin
  } else if (trial % 8 == 6) {
    // A similarity: rotation, uniform scale, translation.
    c.xf = test::random_affine(rng, far, 1.0, 0.0);
    c.xf.linear *= 0.5 + 2.0 * u01(rng);
  }
  return c;
}

// Surface points of the primitive (object space): end balls, hull points and, for
// curves, balls around points of the curve itself.
std::vector<glm::dvec3> samples(const Geometry& g, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0), u01(0.0, 1.0);
  BallHull h = ball_hull(g, 0);
  std::vector<glm::dvec3> pts;
  for (int k = 0; k < 200; ++k) {
    glm::dvec3 dir = glm::normalize(glm::dvec3(u(rng), u(rng), u(rng)));
    int i = k % h.count;
    pts.push_back(h.centre[std::size_t(i)] + h.radius[std::size_t(i)] * dir);
    if (g.type == PrimType::Curve) {
      const CurvePrim& c = g.curves[0];
      double s = u01(rng), t = 1 - s;
      glm::dvec3 p = t * t * t * glm::dvec3(c.p[0]) + 3 * t * t * s * glm::dvec3(c.p[1]) +
                     3 * t * s * s * glm::dvec3(c.p[2]) + s * s * s * glm::dvec3(c.p[3]);
      pts.push_back(p + double(c.radius) * dir);
    }
  }
  return pts;
}

// The worst unit coordinate of world point x under the decoded map plus the decode
// error bound the encoder assumes (8 u |M_kj| |x_j|).
double worst_coordinate(const Affine3& m, const glm::dvec3& x) {
  double worst = 0;
  for (int k = 0; k < 3; ++k) {
    double v = m.translation[k], err = 0;
    for (int j = 0; j < 3; ++j) {
      v += m.linear[j][k] * x[j];
      err += std::abs(m.linear[j][k]) * std::abs(x[j]);
    }
    worst = std::max(worst, std::abs(v) + kMasqDecodeRelError * err);
  }
  return worst;
}

} // namespace

TEST(CompactInstance, EveryPrimitiveMapsInsideUnderTheDecodeBound) {
  std::mt19937_64 rng(17);
  int encoded = 0;
  double area_compact = 0, area_full = 0, worst_ratio = 0;
  for (int trial = 0; trial < 2000; ++trial) {
    Case c = random_case(rng, trial, 1e4);
    SCOPED_TRACE(std::string(prim_type_name(c.g.type)) + " trial " + std::to_string(trial));
    std::optional<CompactMasquerade> cm = compact_masquerade(c.g, 0, c.xf);
    ASSERT_TRUE(cm.has_value()); // every case here is within the form's range
    ++encoded;
    const Affine3 dec = decode_masq_instance(cm->inst);
    for (const glm::dvec3& p : samples(c.g, rng)) ASSERT_LE(worst_coordinate(dec, c.xf.apply_point(p)), 1.0);
    // The same through the support function, exactly: every row's extent.
    BallHull h = ball_hull(c.g, 0);
    Aabb exact = hull_world_box(h, c.xf);
    glm::dvec3 reach = glm::max(glm::abs(exact.lo), glm::abs(exact.hi));
    for (int k = 0; k < 3; ++k) {
      glm::dvec3 row(dec.linear[0][k], dec.linear[1][k], dec.linear[2][k]);
      auto support = [&](const glm::dvec3& v) {
        return h.support(glm::transpose(c.xf.linear) * v) + glm::dot(v, c.xf.translation);
      };
      double ext = std::max(std::abs(support(row) + dec.translation[k]), std::abs(-support(-row) + dec.translation[k]));
      ASSERT_LE(ext + kMasqDecodeRelError * glm::dot(glm::abs(row), reach), 1.0) << "axis " << k;
    }
    // The kernel's own fp32 decode (C++ build of kernels/masq_instance.h) is within the
    // correctly rounded bound, well inside the 8 u the encoder allows.
    kernel::v_default::Affine km = kernel::v_default::affine_from_masq(cm->inst);
    const kernel::vec3 rows[3] = {km.r0, km.r1, km.r2};
    for (int i = 0; i < 3; ++i) {
      EXPECT_EQ(double(km.t[i]), dec.translation[i]);
      for (int j = 0; j < 3; ++j)
        ASSERT_LE(std::abs(double(rows[i][j]) - dec.linear[j][i]), 2.0001 * kU * std::abs(dec.linear[j][i]))
            << "M" << i << j;
    }
    // The world box holds the primitive; unit_to_world inverts the decoded map.
    for (int k = 0; k < 3; ++k) {
      double tol = 1e-12 * (std::abs(exact.lo[k]) + std::abs(exact.hi[k]));
      EXPECT_LE(cm->box.world_box.lo[k], exact.lo[k] + tol);
      EXPECT_GE(cm->box.world_box.hi[k], exact.hi[k] - tol);
    }
    Affine3 round_trip = from_mat3x4f(cm->box.unit_to_world);
    for (int k = 0; k < 8; ++k) {
      glm::dvec3 corner(k & 1 ? 1 : -1, k & 2 ? 1 : -1, k & 4 ? 1 : -1);
      glm::dvec3 back = dec.apply_point(round_trip.apply_point(corner));
      double scale = 1.0 + std::abs(dec.translation.x) + std::abs(dec.translation.y) + std::abs(dec.translation.z);
      EXPECT_NEAR(glm::length(back - corner), 0.0, 1e-5 * scale);
    }
    // Tightness against the 64-byte form, for similarity placements (an affine scene
    // instance makes the 64-byte box a parallelepiped the compact form cannot hold).
    const bool similarity = trial % 8 != 5;
    if (similarity) {
      MasqueradeBox full = masquerade_box(c.g, 0, c.xf);
      area_compact += cm->box.obb_area;
      area_full += full.obb_area;
      // Far from the origin the decode allowance (8 u |M_k| . X per axis, the same order
      // as the kernel's own transform padding there) grows the box by about as much.
      double allowance = 0;
      for (int k = 0; k < 3; ++k)
        allowance = std::max(allowance, kMasqDecodeRelError * glm::dot(glm::abs(glm::dvec3(dec.linear[0][k],
                                                                                            dec.linear[1][k],
                                                                                            dec.linear[2][k])),
                                                                       reach));
      double ratio = cm->box.obb_area / full.obb_area;
      worst_ratio = std::max(worst_ratio, ratio / ((1 + 2 * allowance) * (1 + 2 * allowance)));
    }
  }
  std::printf("compact / 64-byte OBB area: total %.4f, worst %.4f after the decode allowance (%d primitives)\n",
              area_compact / area_full, worst_ratio, encoded);
  EXPECT_LT(area_compact / area_full, 1.02);
  EXPECT_LT(worst_ratio, 1.03);
}

// Near the origin (|centre| within 100 sizes, as hair and fur are) the compact box costs
// only the bfloat16 rounding (<= 2^-7 per axis) and the quaternion's misalignment.
TEST(CompactInstance, NearTheOriginWithinTwoPercentOfTheFullBox) {
  std::mt19937_64 rng(29);
  double worst = 0;
  for (int trial = 0; trial < 1000; ++trial) {
    Case c = random_case(rng, trial, 100.0);
    if (trial % 8 == 5) continue; // affine: see above
    std::optional<CompactMasquerade> cm = compact_masquerade(c.g, 0, c.xf);
    ASSERT_TRUE(cm.has_value());
    worst = std::max(worst, cm->box.obb_area / masquerade_box(c.g, 0, c.xf).obb_area);
  }
  std::printf("near the origin: worst compact / 64-byte OBB area %.4f\n", worst);
  EXPECT_LT(worst, 1.03);
}

TEST(CompactInstance, OwnerBitsLeaveTheScaleAlone) {
  Geometry g;
  g.type = PrimType::Capsule;
  g.capsules.push_back({{0, 0, 0}, {1, 2, 3}, 0.1f});
  std::optional<CompactMasquerade> cm = compact_masquerade(g, 0, {});
  ASSERT_TRUE(cm.has_value());
  Affine3 before = decode_masq_instance(cm->inst);
  set_masq_owner(cm->inst, 65535);
  EXPECT_EQ(kernel::v_default::masq_owner_index(cm->inst), 65535);
  Affine3 after = decode_masq_instance(cm->inst);
  EXPECT_EQ(before.linear, after.linear);
  EXPECT_THROW(set_masq_owner(cm->inst, 65536), std::runtime_error);
}

// The first stage of a block of segments runs in lanes (fit_axes_lanes): its axes and
// first world axis must be the scalar fit_axes's bits, lane by lane, for capsules, round
// cones and ribbons of every direction (axes near x, where perpendicular switches its helper,
// and chords of length 0, where main_axis falls back to z), under identity, rotated and
// sheared maps, in blocks of one to four.
TEST(CompactInstance, AxesInLanesAreTheScalarFitsBits) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0), u01(0.0, 1.0);
  int compared = 0;
  for (int trial = 0; trial < 3000; ++trial) {
    Geometry g;
    const PrimType types[] = {PrimType::Capsule, PrimType::RoundCone, PrimType::Ribbon};
    g.type = types[trial % 3];
    for (int p = 0; p < 4; ++p) {
      glm::dvec3 dir = glm::normalize(glm::dvec3(u(rng), u(rng), u(rng)));
      if (p == 1) dir = glm::normalize(glm::dvec3(1.0, 0.01 * u(rng), 0.01 * u(rng))); // |w.x| >= 0.6
      if (p == 2) dir.x = 0.6 * (u(rng) < 0 ? -1 : 1), dir = glm::normalize(dir);       // about the switch
      const double len = (trial % 7 == 0 && p == 3) ? 0.0 : std::pow(10.0, -3.0 + 4.0 * u01(rng));
      const glm::vec3 a(glm::dvec3(u(rng), u(rng), u(rng)) * 10.0);
      const glm::vec3 b(glm::dvec3(a) + len * dir);
      const float r = float(0.01 + 0.1 * u01(rng));
      if (g.type == PrimType::Capsule) g.capsules.push_back({a, b, r});
      if (g.type == PrimType::RoundCone) g.round_cones.push_back({a, r, b, 0.5f * r});
      if (g.type == PrimType::Ribbon) g.ribbons.push_back({a, r, b, 0.5f * r, glm::vec3(0, 0, 1)});
    }
    Affine3 xf;
    if ((trial / 3) % 3 == 1) xf = test::random_affine(rng, 5.0, 1.0, 0.0);
    if ((trial / 3) % 3 == 2) xf = test::random_affine(rng, 5.0, 0.2, 3.0);
    const int n = 1 + trial % 4;
    const std::int32_t prims[4] = {0, 1, 2, 3};
    compact_fit::CompactFit lane[4], alone[4];
    compact_fit::CompactFit* lanes[4] = {&lane[0], &lane[1], &lane[2], &lane[3]};
    compact_fit::fit_axes_lanes(lanes, n, g, prims, xf);
    for (int l = 0; l < n; ++l) {
      compact_fit::fit_hull(alone[l], g, std::size_t(l));
      compact_fit::fit_axes(alone[l], g, xf);
      for (int c = 0; c < 3; ++c)
        for (int k = 0; k < 3; ++k)
          EXPECT_EQ(std::bit_cast<std::uint64_t>(lane[l].axes[c][k]), std::bit_cast<std::uint64_t>(alone[l].axes[c][k]))
              << "trial " << trial << " lane " << l << " axis " << c << " component " << k;
      for (int k = 0; k < 3; ++k)
        EXPECT_EQ(std::bit_cast<std::uint64_t>(lane[l].a0[k]), std::bit_cast<std::uint64_t>(alone[l].a0[k]))
            << "trial " << trial << " lane " << l << " a0 component " << k;
      ++compared;
    }
  }
  EXPECT_EQ(compared, 7500);
}
