// Scene description files (.json): files and generators combined with transforms, the
// camera, path resolution (relative, ${MASQ_DATA}), and one broken input per error class.
#include "masq/error.h"
#include "scenes/loaders/load_description.h"
#include <gtest/gtest.h>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <unistd.h>
#include <vector>

using namespace masq;
namespace fs = std::filesystem;

namespace {

void expect_error(const std::function<void()>& f, const std::vector<std::string>& parts) {
  try {
    f();
  } catch (const Error& e) {
    std::string msg = e.what();
    for (const std::string& p : parts) EXPECT_NE(msg.find(p), std::string::npos) << "'" << p << "' not in: " << msg;
    return;
  }
  ADD_FAILURE() << "expected masq::Error";
}

Scene text(const std::string& json) { return load_description_text(json, "scene.json", ""); }

// A fresh directory per test (ctest runs tests as parallel processes).
struct TempDir {
  fs::path path;
  TempDir() {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    path = fs::temp_directory_path() /
           ("masq_desc_" + std::to_string(::getpid()) + "_" + info->test_suite_name() + "_" + info->name());
    fs::remove_all(path);
    fs::create_directories(path);
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
  void write(const std::string& rel, const std::string& content) const {
    fs::create_directories((path / rel).parent_path());
    std::ofstream(path / rel, std::ios::binary) << content;
  }
};

void expect_near3(const glm::dvec3& a, const glm::dvec3& b, double tol = 1e-6) {
  EXPECT_NEAR(a.x, b.x, tol);
  EXPECT_NEAR(a.y, b.y, tol);
  EXPECT_NEAR(a.z, b.z, tol);
}

} // namespace

TEST(SceneDescription, CombinesGeneratorsAndFileWithTransforms) {
  const std::string bunny = std::string(MASQ_DATA_DIR) + "/meshes/bun_zipper.ply";
  if (!fs::exists(bunny)) GTEST_SKIP() << "data file " << bunny << " is absent (shared data not installed)";
  const std::string json = R"({
    "name": "combo",
    "objects": [
      {"generator": "bundle", "count": 100, "radius": 0.01, "tilt": 30, "seed": 7,
       "transform": {"translate": [10, 0, 0], "scale": 2}},
      {"generator": "ground", "height": 0, "size": 2,
       "transform": {"translate": [0, -1, 0], "scale": [3, 1, 3]}},
      {"file": ")" + bunny + R"(",
       "transform": {"translate": [0, 0, 5], "rotate": {"axis": [0, 1, 0], "deg": 90}}}
    ]})";
  Scene s = text(json);
  EXPECT_EQ(s.name, "combo");
  ASSERT_EQ(s.geometries.size(), 3u);
  ASSERT_EQ(s.instances.size(), 3u);
  EXPECT_EQ(s.geometries[0].type, PrimType::Capsule);
  EXPECT_EQ(s.geometries[0].capsules.size(), 100u);
  EXPECT_EQ(s.geometries[1].triangles.size(), 2u);
  EXPECT_EQ(s.geometries[2].triangles.size(), 69451u);
  EXPECT_EQ(s.primitive_count(), 100u + 2u + 69451u);

  // Bundle: scale 2, then translate.
  const Instance& b = s.instances[0];
  ASSERT_EQ(b.geometry, 0u);
  glm::dvec3 a(s.geometries[0].capsules[0].a);
  expect_near3(b.object_to_world.apply_point(a), 2.0 * a + glm::dvec3(10, 0, 0));

  // Ground: vertex (-2, 0, -2) scaled by (3, 1, 3), moved down by 1.
  const Instance& g = s.instances[1];
  ASSERT_EQ(g.geometry, 1u);
  expect_near3(g.object_to_world.apply_point(glm::dvec3(s.geometries[1].vertices[0])), {-6, -1, -6});

  // Bunny: +90 deg about y maps (x, y, z) to (z, y, -x), then translate.
  const Instance& m = s.instances[2];
  ASSERT_EQ(m.geometry, 2u);
  glm::dvec3 v(s.geometries[2].vertices[0]);
  expect_near3(m.object_to_world.apply_point(v), glm::dvec3(v.z, v.y, -v.x + 5.0), 1e-9);

  // No camera given: framed, looking at the scene.
  EXPECT_FALSE(s.camera.orthographic);
  EXPECT_TRUE(std::isfinite(s.camera.eye.x) && std::isfinite(s.camera.target.x));
  EXPECT_NE(s.camera.eye, s.camera.target);
}

TEST(SceneDescription, Camera) {
  Scene p = text(R"({"camera": {"eye": [1, 2, 3], "target": [0, 0.5, 0], "up": [0, 0, 1], "fov": 30},
                     "objects": [{"generator": "ground"}]})");
  EXPECT_EQ(p.name, "scene");
  EXPECT_EQ(p.camera.eye, glm::dvec3(1, 2, 3));
  EXPECT_EQ(p.camera.target, glm::dvec3(0, 0.5, 0));
  EXPECT_EQ(p.camera.up, glm::dvec3(0, 0, 1));
  EXPECT_EQ(p.camera.fov_y_deg, 30.0);
  EXPECT_FALSE(p.camera.orthographic);

  Scene o = text(R"({"camera": {"eye": [0, 0, -4], "target": [0, 0, 0], "ortho_height": 2.5},
                     "objects": [{"generator": "ground"}]})");
  EXPECT_TRUE(o.camera.orthographic);
  EXPECT_EQ(o.camera.ortho_height, 2.5);
  EXPECT_EQ(o.camera.up, glm::dvec3(0, 1, 0));
  EXPECT_EQ(o.camera.fov_y_deg, 40.0);

  expect_error([] { text(R"({"camera": {"eye": [0, 0, 1]}, "objects": [{"generator": "ground"}]})"); },
               {"scene.json: camera.target: missing"});
  expect_error([] { text(R"({"camera": {"eye": [0, 0], "target": [0, 0, 0]}, "objects": [{"generator": "ground"}]})"); },
               {"scene.json: camera.eye: expected [x,y,z]"});
}

TEST(SceneDescription, StrandGeneratorsPrimAndSubdiv) {
  Scene h = text(R"({"objects": [{"generator": "hair", "strands": 5, "points": 4, "prim": "curve"}]})");
  Scene h2 = text(R"({"objects": [{"generator": "hair", "strands": 5, "points": 4, "prim": "curve", "subdiv": 2}]})");
  ASSERT_EQ(h.geometries.size(), 1u);
  EXPECT_EQ(h.geometries[0].type, PrimType::Curve);
  EXPECT_GT(h.primitive_count(), 0u);
  EXPECT_EQ(h2.primitive_count(), 2 * h.primitive_count());

  Scene f = text(R"({"objects": [{"generator": "fur", "strands": 5, "points": 3, "prim": "capsule"}]})");
  EXPECT_EQ(f.geometries[0].type, PrimType::Capsule);
  EXPECT_EQ(f.primitive_count(), 10u);

  Scene sl = text(R"({"objects": [{"generator": "streamlines", "lines": 3, "steps": 10, "radius": 0.01, "seed": 2}]})");
  EXPECT_EQ(sl.geometries[0].type, PrimType::RoundCone);
  EXPECT_GT(sl.primitive_count(), 0u);

  Scene b = text(R"({"objects": [{"generator": "bundle", "count": 4, "prim": "cone"}]})");
  EXPECT_EQ(b.geometries[0].type, PrimType::RoundCone);
  EXPECT_EQ(b.primitive_count(), 4u);
}

TEST(SceneDescription, RelativePathResolvesAgainstDescriptionDir) {
  TempDir d;
  d.write("sub/ball.nff", "s 1 2 3 0.5\n");
  d.write("scene.json", R"({"objects": [{"file": "sub/ball.nff", "transform": {"translate": [1, 0, 0]}}]})");
  Scene s = load_description((d.path / "scene.json").string());
  EXPECT_EQ(s.name, "scene");
  ASSERT_EQ(s.geometries.size(), 1u);
  ASSERT_EQ(s.geometries[0].spheres.size(), 1u);
  ASSERT_EQ(s.instances.size(), 1u);
  expect_near3(s.instances[0].object_to_world.apply_point(glm::dvec3(s.geometries[0].spheres[0].center)), {2, 2, 3});
}

TEST(SceneDescription, MasqDataExpansion) {
  TempDir d;
  d.write("nff/ball.nff", "s 0 0 0 0.25\ns 1 0 0 0.25\n");
  ::setenv("MASQ_DATA", d.path.string().c_str(), 1);
  Scene s = load_description_text(R"({"objects": [{"file": "${MASQ_DATA}/nff/ball.nff"}]})", "scene.json", "/nonexistent");
  ::unsetenv("MASQ_DATA");
  ASSERT_EQ(s.geometries.size(), 1u);
  EXPECT_EQ(s.geometries[0].spheres.size(), 2u);
}

TEST(SceneDescriptionBad, SyntaxError) {
  expect_error([] { text(R"({"objects": [ {"generator": "ground"} ,, ]})"); }, {"scene.json", "syntax error", "byte 40"});
}

TEST(SceneDescriptionBad, UnknownKey) {
  expect_error([] { text(R"({"objects": [{"generator": "ground", "transform": {"scael": 2}}]})"); },
               {"scene.json: objects[0].transform.scael: unknown key"});
  expect_error([] { text(R"({"object": []})"); }, {"scene.json: object: unknown key"});
  expect_error([] { text(R"({"objects": [{"generator": "bundle", "cuont": 3}]})"); },
               {"scene.json: objects[0].cuont: unknown key"});
}

TEST(SceneDescriptionBad, WrongType) {
  expect_error(
      [] {
        text(R"({"objects": [{"generator": "ground"}, {"generator": "ground"},
                             {"generator": "ground", "transform": {"scale": "big"}}]})");
      },
      {"scene.json: objects[2].transform.scale: expected a number or [x,y,z]"});
  expect_error([] { text(R"({"objects": [{"generator": "bundle", "count": 2.5}]})"); },
               {"scene.json: objects[0].count: expected an integer"});
  expect_error([] { text(R"({"objects": [{"file": 3}]})"); }, {"scene.json: objects[0].file: expected a string"});
  expect_error([] { text(R"({"objects": {}})"); }, {"scene.json: objects: expected a non-empty array"});
}

TEST(SceneDescriptionBad, UnknownGeneratorOrPrim) {
  expect_error([] { text(R"({"objects": [{"generator": "hairball"}]})"); },
               {"scene.json: objects[0].generator: unknown generator 'hairball'"});
  expect_error([] { text(R"({"objects": [{"generator": "bundle", "prim": "cylinder"}]})"); },
               {"scene.json: objects[0].prim: unknown primitive type 'cylinder'"});
  expect_error([] { text(R"({"objects": [{"file": "x.nff", "prim": "curve"}]})"); },
               {"scene.json: objects[0].prim: unknown primitive type 'curve'"});
}

TEST(SceneDescriptionBad, MissingFile) {
  TempDir d;
  d.write("scene.json", R"({"objects": [{"generator": "ground"}, {"file": "nope.ply"}]})");
  const std::string p = (d.path / "scene.json").string();
  expect_error([&] { load_description(p); }, {p + ": objects[1].file: ", (d.path / "nope.ply").string()});
}

TEST(SceneDescriptionBad, UnsetMasqData) {
  ::unsetenv("MASQ_DATA");
  expect_error([] { text(R"({"objects": [{"file": "${MASQ_DATA}/meshes/bun_zipper.ply"}]})"); },
               {"scene.json: objects[0].file:", "MASQ_DATA", "not set"});
}
