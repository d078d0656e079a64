// Bad scenes get a clear error naming the element, never a crash or a silent NaN.
#include "bvh/twolevel/build_accel.h"
#include "masq/error.h"
#include "scenes/generators.h"
#include <gtest/gtest.h>
#include <cmath>

using namespace masq;

namespace {
std::string error_of(const Scene& s) {
  try {
    build_accel(s, Method::Masq);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}
Scene one_capsule(CapsulePrim c) {
  Scene s;
  s.name = std::string("one capsule");
  Geometry g;
  g.type = PrimType::Capsule;
  g.capsules.push_back(c);
  s.geometries.push_back(g);
  s.instances.push_back({0, {}});
  return s;
}
} // namespace

TEST(SceneValidation, EmptySceneIsAnError) {
  Scene s;
  s.name = "empty";
  EXPECT_NE(error_of(s).find("empty scene"), std::string::npos);
}

TEST(SceneValidation, SingularTransformNamesTheInstance) {
  Scene s = make_default_scene();
  s.instances[1].object_to_world.linear[2] = glm::dvec3(0.0);
  EXPECT_NE(error_of(s).find("instance 1 has a singular transform"), std::string::npos);
}

TEST(SceneValidation, NanTransformAndNanPointsAreErrors) {
  Scene s = make_default_scene();
  s.instances[0].object_to_world.translation.y = std::nan("");
  EXPECT_NE(error_of(s).find("instance 0"), std::string::npos);
  Scene t = one_capsule({{0, 0, 0}, {NAN, 0, 0}, 0.1f});
  EXPECT_NE(error_of(t).find("capsule 0 has a non-finite endpoint"), std::string::npos);
}

TEST(SceneValidation, NegativeRadiusAndBadIndicesAreErrors) {
  EXPECT_NE(error_of(one_capsule({{0, 0, 0}, {1, 0, 0}, -0.1f})).find("radius"), std::string::npos);
  Scene s = make_default_scene();
  s.geometries[1].triangles[0].y = 99;
  EXPECT_NE(error_of(s).find("geometry 1 triangle 0 indexes a vertex"), std::string::npos);
  Scene u = make_default_scene();
  u.instances[0].geometry = 7;
  EXPECT_NE(error_of(u).find("names geometry 7"), std::string::npos);
}

TEST(SceneValidation, DegenerateCapsulesAreHandled) {
  // Zero length is a sphere; zero radius has no surface (never hit, no masquerade box).
  Scene s = one_capsule({{0, 0, 0}, {0, 0, 0}, 0.1f});
  s.geometries[0].capsules.push_back({{1, 0, 0}, {2, 0, 0}, 0.0f});
  PackedScene ps = build_accel(s, Method::Masq);
  EXPECT_EQ(ps.tlas_entry_count(), 1u);
  EXPECT_NO_THROW(build_accel(s, Method::Ref));
}

// Beyond 2^60 from the origin the intersectors' squared distances overflow fp32 and every
// ray would miss: refused, naming the element, the reach and the limit (docs/robustness.md,
// "Scene range"). Within it, accepted.
TEST(SceneValidation, RangeBeyondFp32IsRefused) {
  const float near_limit = 1e18f, beyond = 1e19f;
  EXPECT_EQ(error_of(one_capsule({{near_limit, 0, 0}, {near_limit, 1e17f, 0}, 1e16f})), "");
  const std::string far = error_of(one_capsule({{beyond, 0, 0}, {beyond, 1e18f, 0}, 1e17f}));
  EXPECT_NE(far.find("geometry 0 reaches 1.01e+19"), std::string::npos) << far;
  EXPECT_NE(far.find("2^60 (1.15e+18)"), std::string::npos) << far;
  // A radius alone can reach too far.
  EXPECT_NE(error_of(one_capsule({{0, 0, 0}, {1, 0, 0}, beyond})).find("geometry 0 reaches"), std::string::npos);
  // In range in object space, out of it in world space: the instance is named.
  Scene scaled = one_capsule({{near_limit, 0, 0}, {near_limit, 1e17f, 0}, 1e16f});
  scaled.instances[0].object_to_world.linear = glm::dmat3(10.0);
  EXPECT_NE(error_of(scaled).find("instance 0 reaches 1.02e+19"), std::string::npos) << error_of(scaled);
  Scene moved = one_capsule({{0, 0, 0}, {1, 0, 0}, 0.1f});
  moved.instances[0].object_to_world.translation = glm::dvec3(0.0, -2e18, 0.0);
  EXPECT_NE(error_of(moved).find("instance 0 reaches 2e+18"), std::string::npos) << error_of(moved);
}
