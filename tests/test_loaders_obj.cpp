// Wavefront OBJ loader: faces (quads triangulated, relative indices), `l` polylines as
// capsules / round cones, mixed files, path == memory, and one broken input per error.
#include "masq/error.h"
#include "scenes/loaders/load_obj.h"
#include <gtest/gtest.h>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

using namespace masq;

namespace {

std::vector<std::byte> bytes_of(const std::string& s) {
  std::vector<std::byte> b(s.size());
  if (!s.empty()) std::memcpy(b.data(), s.data(), s.size());
  return b;
}

Scene obj(const std::string& s, const LoadOptions& opt = {}) { return load_obj(bytes_of(s), "test.obj", opt); }

// Error message of loading `s`, or "" when it loads.
std::string obj_error(const std::string& s) {
  try {
    obj(s);
  } catch (const Error& e) {
    return e.what();
  }
  return {};
}

const char* kQuadAndTriangle =
    "# a unit quad and a triangle\n"
    "mtllib missing.mtl\n"
    "o mesh\n"
    "v 0 0 0\n"
    "v 1 0 0\n"
    "v 1 1 0\n"
    "v 0 1 0\n"
    "v 2 0 0\n"
    "vn 0 0 1\n"
    "usemtl nothing\n"
    "f 1//1 2//1 3//1 4//1\n"
    "f 2 5 3\n";

const char* kPolyline =
    "v 0 0 0\n"
    "v 1 0 0\n"
    "v 1 1 0\n"
    "v 1 1 1\n"
    "l 1 2 3 4\n";

} // namespace

TEST(LoadObj, QuadAndTriangleGiveThreeTriangles) {
  std::vector<std::string> warnings;
  LoadOptions opt;
  opt.warn = [&](const std::string& w) { warnings.push_back(w); };
  Scene s = obj(kQuadAndTriangle, opt);
  ASSERT_EQ(s.geometries.size(), 1u);
  ASSERT_EQ(s.instances.size(), 1u);
  const Geometry& g = s.geometries[0];
  EXPECT_EQ(g.type, PrimType::Triangle);
  EXPECT_EQ(g.vertices.size(), 5u);
  ASSERT_EQ(g.triangles.size(), 3u);
  EXPECT_EQ(g.vertices[4], glm::vec3(2, 0, 0));
  EXPECT_EQ(g.triangles[2], glm::uvec3(1, 4, 2));
  // The two quad triangles cover all four quad corners.
  std::vector<bool> seen(5, false);
  for (int t = 0; t < 2; ++t)
    for (int k = 0; k < 3; ++k) seen[g.triangles[t][k]] = true;
  EXPECT_TRUE(seen[0] && seen[1] && seen[2] && seen[3]);
  EXPECT_FALSE(warnings.empty());  // the missing material is reported, not fatal
  EXPECT_NO_THROW(validate_scene(s));
}

TEST(LoadObj, RelativeIndices) {
  Scene a = obj("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nv 5 5 5\nv 6 5 5\nv 5 6 5\nf 4 5 6\n");
  Scene b = obj("v 0 0 0\nv 1 0 0\nv 0 1 0\nf -3 -2 -1\nv 5 5 5\nv 6 5 5\nv 5 6 5\nf -3 -2 -1\n");
  ASSERT_EQ(b.geometries.size(), 1u);
  ASSERT_EQ(b.geometries[0].triangles.size(), 2u);
  EXPECT_EQ(a.geometries[0].triangles, b.geometries[0].triangles);
  EXPECT_EQ(b.geometries[0].triangles[1], glm::uvec3(3, 4, 5));
}

TEST(LoadObj, PolylineAsCapsules) {
  LoadOptions opt;
  opt.radius = 0.25f;
  Scene s = obj(kPolyline, opt);
  ASSERT_EQ(s.geometries.size(), 1u);
  const Geometry& g = s.geometries[0];
  EXPECT_EQ(g.type, PrimType::Capsule);
  ASSERT_EQ(g.capsules.size(), 3u);
  EXPECT_EQ(g.capsules[0].a, glm::vec3(0, 0, 0));
  EXPECT_EQ(g.capsules[0].b, glm::vec3(1, 0, 0));
  EXPECT_EQ(g.capsules[2].a, glm::vec3(1, 1, 0));
  EXPECT_EQ(g.capsules[2].b, glm::vec3(1, 1, 1));
  for (const CapsulePrim& c : g.capsules) EXPECT_FLOAT_EQ(c.radius, 0.25f);
  EXPECT_NO_THROW(validate_scene(s));
}

TEST(LoadObj, PolylineAsRoundConesWithDefaultRadius) {
  std::vector<std::string> warnings;
  LoadOptions opt;
  opt.strand_type = PrimType::RoundCone;
  opt.warn = [&](const std::string& w) { warnings.push_back(w); };
  Scene s = obj(kPolyline, opt);
  ASSERT_EQ(s.geometries.size(), 1u);
  const Geometry& g = s.geometries[0];
  EXPECT_EQ(g.type, PrimType::RoundCone);
  ASSERT_EQ(g.round_cones.size(), 3u);
  const float expected = 0.002f * std::sqrt(3.0f);  // bounding box (0,0,0)-(1,1,1)
  for (const RoundConePrim& c : g.round_cones) {
    EXPECT_NEAR(c.ra, expected, 1e-6f);
    EXPECT_NEAR(c.rb, expected, 1e-6f);
  }
  EXPECT_EQ(g.round_cones[1].a, glm::vec3(1, 0, 0));
  EXPECT_EQ(g.round_cones[1].b, glm::vec3(1, 1, 0));
  ASSERT_FALSE(warnings.empty());
  EXPECT_NE(warnings.back().find("radius"), std::string::npos) << warnings.back();
}

TEST(LoadObj, NonStrandTypeRejected) {
  LoadOptions opt;
  opt.strand_type = PrimType::Sphere;
  EXPECT_THROW(obj(kPolyline, opt), Error);
}

TEST(LoadObj, FacesAndLinesGiveTwoGeometries) {
  Scene s = obj(std::string(kQuadAndTriangle) + "l 1 3 5\nl -1 -2\n");
  ASSERT_EQ(s.geometries.size(), 2u);
  ASSERT_EQ(s.instances.size(), 2u);
  EXPECT_EQ(s.geometries[0].type, PrimType::Triangle);
  EXPECT_EQ(s.geometries[0].triangles.size(), 3u);
  EXPECT_EQ(s.geometries[1].type, PrimType::Capsule);
  ASSERT_EQ(s.geometries[1].capsules.size(), 3u);
  EXPECT_EQ(s.geometries[1].capsules[2].a, glm::vec3(2, 0, 0));
  EXPECT_EQ(s.geometries[1].capsules[2].b, glm::vec3(0, 1, 0));
  EXPECT_EQ(s.instances[0].geometry, 0u);
  EXPECT_EQ(s.instances[1].geometry, 1u);
  EXPECT_NO_THROW(validate_scene(s));
}

TEST(LoadObj, PathEqualsMemory) {
  const std::string text = std::string(kQuadAndTriangle) + "l 1 2 3 4\n";
  const std::filesystem::path p =
      std::filesystem::temp_directory_path() / ("masq_test_obj_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) + ".obj");
  {
    std::ofstream f(p, std::ios::binary);
    f << text;
  }
  LoadOptions opt;
  opt.radius = 0.1f;
  Scene a = load_obj(p.string(), opt);
  Scene b = load_obj(bytes_of(text), p.string(), opt);
  std::filesystem::remove(p);
  EXPECT_EQ(a.name, p.string());
  ASSERT_EQ(a.geometries.size(), 2u);
  ASSERT_EQ(b.geometries.size(), 2u);
  EXPECT_EQ(a.geometries[0].vertices, b.geometries[0].vertices);
  EXPECT_EQ(a.geometries[0].triangles, b.geometries[0].triangles);
  ASSERT_EQ(a.geometries[1].capsules.size(), b.geometries[1].capsules.size());
  for (std::size_t i = 0; i < a.geometries[1].capsules.size(); ++i) {
    EXPECT_EQ(a.geometries[1].capsules[i].a, b.geometries[1].capsules[i].a);
    EXPECT_EQ(a.geometries[1].capsules[i].b, b.geometries[1].capsules[i].b);
    EXPECT_EQ(a.geometries[1].capsules[i].radius, b.geometries[1].capsules[i].radius);
  }
}

TEST(LoadObj, NanVertexIsAnError) {
  std::string e = obj_error("v 0 0 0\nv 1 nan 0\nv 0 1 0\nf 1 2 3\n");
  EXPECT_NE(e.find("test.obj"), std::string::npos) << e;
  EXPECT_NE(e.find("vertex 2"), std::string::npos) << e;
  EXPECT_NE(e.find("line 2"), std::string::npos) << e;
  e = obj_error("v 0 0 0\nv 1 0 0\nv 0 1 inf\nf 1 2 3\n");
  EXPECT_NE(e.find("vertex 3"), std::string::npos) << e;
  e = obj_error("v 0 0 0\nv 1e400 0 0\nv 0 1 0\nf 1 2 3\n");
  EXPECT_NE(e.find("vertex 2"), std::string::npos) << e;
}

TEST(LoadObj, IndexOutOfRangeIsAnError) {
  const std::string verts = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
  for (const std::string& bad : {verts + "f 1 2 7\n", verts + "f 1 2 3 9\n", verts + "f 1 2 -9\n",
                                 verts + "l 1 2 5\n", verts + "l -7 1\n", verts + "f 1 2 3\nf 1 2 4\n"}) {
    std::string e = obj_error(bad);
    EXPECT_FALSE(e.empty()) << bad;
    EXPECT_NE(e.find("test.obj"), std::string::npos) << e;
  }
  std::string e = obj_error(verts + "f 1 2 7\n");
  EXPECT_NE(e.find("line 4"), std::string::npos) << e;
  e = obj_error(verts + "f 0 1 2\n");  // zero index: a tinyobjloader parse error
  EXPECT_NE(e.find("line 4"), std::string::npos) << e;
}

TEST(LoadObj, EmptyInputsAreErrors) {
  EXPECT_NE(obj_error("").find("nothing to load"), std::string::npos);
  EXPECT_NE(obj_error("# only a comment\nv 0 0 0\nv 1 0 0\n").find("nothing to load"), std::string::npos);
  EXPECT_FALSE(obj_error("v 0 0 0\np 1\n").empty());
}

TEST(LoadObj, MissingPathIsAnError) {
  try {
    load_obj("/nonexistent/dir/masq_missing.obj");
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("masq_missing.obj"), std::string::npos) << e.what();
  }
}
