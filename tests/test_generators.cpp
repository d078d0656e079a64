// Embedded strand generators: counts, determinism, valid scenes, every primitive form.
#include "bvh/twolevel/build_accel.h"
#include "scenes/strand_generators.h"
#include <gtest/gtest.h>

using namespace masq;

TEST(Generators, HairCountsAndDeterminism) {
  HairParams p;
  p.strands = 500;
  p.points = 8;
  for (PrimType t : {PrimType::Capsule, PrimType::RoundCone, PrimType::Curve}) {
    p.type = t;
    Scene a = make_hair_scene(p), b = make_hair_scene(p);
    ASSERT_EQ(a.primitive_count(), std::size_t(500 * 7)) << prim_type_name(t);
    EXPECT_NO_THROW(validate_scene(a));
    EXPECT_NO_THROW(build_accel(a, Method::Masq));
    // Same seed, same scene.
    const Geometry &ga = a.geometries[0], &gb = b.geometries[0];
    if (t == PrimType::Curve) {
      EXPECT_EQ(ga.curves.back().p[3], gb.curves.back().p[3]);
    }
    if (t == PrimType::Capsule) {
      EXPECT_EQ(ga.capsules.back().b, gb.capsules.back().b);
    }
  }
  // Another seed, another scene.
  p.type = PrimType::Capsule;
  HairParams q = p;
  q.seed = 2;
  Scene a = make_hair_scene(p), b = make_hair_scene(q);
  EXPECT_NE(a.geometries[0].capsules.back().b, b.geometries[0].capsules.back().b);
}

TEST(Generators, HairRootsOnTheirSurface) {
  HairParams p;
  p.strands = 200;
  for (HairSurface s : {HairSurface::Sphere, HairSurface::Head, HairSurface::Body}) {
    p.surface = s;
    for (const Strand& st : grow_hair(p)) {
      glm::dvec3 r = st.points.front();
      glm::dvec3 scaled = s == HairSurface::Body ? r / glm::dvec3(2, 1, 1) : r;
      EXPECT_NEAR(glm::length(scaled), 1.0, 1e-9);
      if (s == HairSurface::Head) {
        EXPECT_GE(r.y, -0.1 - 1e-9);
      }
      EXPECT_NEAR(st.radii.front(), p.radius, 1e-12);
      EXPECT_NEAR(st.radii.back(), 0.5 * p.radius, 1e-12); // tips taper to half
    }
  }
}

TEST(Generators, StreamlinesFollowTheFlow) {
  StreamlineParams p;
  p.lines = 50;
  p.steps = 40;
  std::vector<Strand> lines = trace_streamlines(p);
  ASSERT_EQ(lines.size(), 50u);
  for (const Strand& s : lines) {
    ASSERT_EQ(s.points.size(), 41u);
    // RK4 on the normalised field: consecutive points one step of arc apart; the chord
    // of a curved step is a little shorter (5% covers the ABC flow's sharpest turns).
    for (std::size_t i = 1; i < s.points.size(); ++i) {
      double chord = glm::length(s.points[i] - s.points[i - 1]);
      EXPECT_LE(chord, p.step * (1 + 1e-9));
      EXPECT_GE(chord, 0.95 * p.step);
    }
  }
  Scene sc = make_streamline_scene(p);
  EXPECT_EQ(sc.primitive_count(), std::size_t(50 * 40));
  EXPECT_NO_THROW(build_accel(sc, Method::Masq));
}

TEST(Generators, CurvesInterpolateThePolyline) {
  // Catmull-Rom pieces pass through every strand point.
  std::vector<Strand> tubes = make_random_tubes(20, 6, 0.01, 3);
  Geometry g = strands_to_geometry(tubes, PrimType::Curve);
  ASSERT_EQ(g.curves.size(), std::size_t(20 * 5));
  for (std::size_t s = 0; s < tubes.size(); ++s)
    for (std::size_t i = 0; i < 5; ++i) {
      const CurvePrim& c = g.curves[s * 5 + i];
      EXPECT_EQ(c.p[0], glm::vec3(tubes[s].points[i]));
      EXPECT_EQ(c.p[3], glm::vec3(tubes[s].points[i + 1]));
    }
  Strand bad;
  bad.points = {{0, 0, 0}, {1, 0, 0}};
  bad.radii = {0.1};
  EXPECT_THROW(strands_to_geometry({bad}, PrimType::Capsule), std::runtime_error);
  EXPECT_THROW(grow_hair(HairParams{.strands = 0}), std::runtime_error);
}
