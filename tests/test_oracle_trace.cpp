// Oracle::trace: every primitive type through a transformed instance, the brute-force
// nearest hit over the scene.
#include "oracle/oracle.h"
#include "tests/oracle_test_util.h"
#include <gtest/gtest.h>
#include <cstdint>

using namespace masq;
using namespace masq::oracle;
using namespace masq::test;

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
  cone.round_cones = {{{0, 0, 0}, 0.5f, {2, 0, 0}, 0.25f}};
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
