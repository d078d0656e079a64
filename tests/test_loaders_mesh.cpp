// PLY and NFF loaders: real data (Stanford bunny, SPD 3.14 scenes), binary/ASCII
// equivalence, strands, three-line NFF round cones, and one broken input per error class.
#include "masq/error.h"
#include "scenes/loaders/load_nff.h"
#include "scenes/loaders/load_ply.h"
#include <gtest/gtest.h>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <functional>
#include <limits>
#include <string>
#include <vector>

using namespace masq;

namespace {

std::string data_path(const std::string& rel) { return std::string(MASQ_DATA_DIR) + "/" + rel; }

#define SKIP_IF_ABSENT(p)                                                                              \
  if (!std::filesystem::exists(p)) GTEST_SKIP() << "data file " << (p) << " is absent (shared data not installed)"

std::vector<std::byte> bytes_of(const std::string& s) {
  std::vector<std::byte> b(s.size());
  if (!s.empty()) std::memcpy(b.data(), s.data(), s.size()); // memcpy(nullptr, .., 0) is UB (UBSan)
  return b;
}

Scene ply(const std::string& s, const LoadOptions& opt = {}) { return load_ply(bytes_of(s), "test.ply", opt); }
Scene ply(const std::vector<std::byte>& b, const LoadOptions& opt = {}) { return load_ply(b, "test.ply", opt); }
Scene nff(const std::string& s, const LoadOptions& opt = {}) { return load_nff(bytes_of(s), "test.nff", opt); }

// Runs f, which must throw masq::Error whose text contains every one of `parts`.
void expect_error(const std::function<void()>& f, const std::vector<std::string>& parts) {
  try {
    f();
  } catch (const Error& e) {
    std::string msg = e.what();
    for (const std::string& p : parts) EXPECT_NE(msg.find(p), std::string::npos) << "'" << p << "' not in: " << msg;
    return;
  }
  ADD_FAILURE() << "no masq::Error thrown";
}

const Geometry* find_geom(const Scene& s, PrimType t) {
  for (const Geometry& g : s.geometries)
    if (g.type == t) return &g;
  return nullptr;
}

// ---- a small PLY writer (ASCII / binary LE / binary BE)
struct PlyVertex { float x, y, z; unsigned char quality; };

template <class T>
void put(std::vector<std::byte>& out, T v, bool big) {
  unsigned char b[sizeof(T)];
  std::memcpy(b, &v, sizeof(T));
  if (big) std::reverse(b, b + sizeof(T));
  for (unsigned char c : b) out.push_back(static_cast<std::byte>(c));
}

std::vector<std::byte> write_ply(const std::vector<PlyVertex>& vs, const std::vector<std::vector<int>>& faces,
                                 const std::string& format) {
  std::string h = "ply\nformat ";
  h += format;
  h += " 1.0\ncomment written by test_loaders_mesh\nelement vertex ";
  h += std::to_string(vs.size());
  h += "\nproperty float x\nproperty float y\nproperty float z\nproperty uchar quality\nelement face ";
  h += std::to_string(faces.size());
  h += "\nproperty list uchar int vertex_indices\nend_header\n";
  if (format == "ascii") {
    for (const PlyVertex& v : vs)
      h += std::to_string(v.x) + " " + std::to_string(v.y) + " " + std::to_string(v.z) + " " + std::to_string(v.quality) + "\n";
    for (const auto& f : faces) {
      h += std::to_string(f.size());
      for (int i : f) {
        h += ' ';
        h += std::to_string(i);
      }
      h += "\n";
    }
    return bytes_of(h);
  }
  bool big = format == "binary_big_endian";
  std::vector<std::byte> out = bytes_of(h);
  for (const PlyVertex& v : vs) {
    put(out, v.x, big); put(out, v.y, big); put(out, v.z, big); put(out, v.quality, big);
  }
  for (const auto& f : faces) {
    put(out, static_cast<unsigned char>(f.size()), big);
    for (int i : f) put(out, static_cast<std::int32_t>(i), big);
  }
  return out;
}

const std::vector<PlyVertex> kVerts = {{0, 0, 0, 1}, {1, 0, 0, 2}, {1, 1, 0, 3}, {0, 1, 0, 4}, {0.5f, 0.5f, 1, 5}};
const std::vector<std::vector<int>> kFaces = {{0, 1, 2, 3}, {0, 1, 4}, {1, 2, 4}, {2, 3, 4, 0, 1}};

} // namespace

// ================= real data

TEST(PlyReal, StanfordBunny) {
  const std::string p = data_path("meshes/bun_zipper.ply");
  SKIP_IF_ABSENT(p);
  Scene s = load_ply(p);
  ASSERT_EQ(s.geometries.size(), 1u);
  ASSERT_EQ(s.instances.size(), 1u);
  const Geometry& g = s.geometries[0];
  EXPECT_EQ(g.type, PrimType::Triangle);
  EXPECT_EQ(g.vertices.size(), 35947u);
  EXPECT_EQ(g.triangles.size(), 69451u);
  EXPECT_NO_THROW(validate_scene(s));
  EXPECT_NEAR(g.vertices[0].x, -0.0378297f, 1e-6f);
}

struct SpdCase { const char* file; std::size_t round_cones, spheres; };

class NffReal : public ::testing::TestWithParam<SpdCase> {};

TEST_P(NffReal, Counts) {
  const SpdCase c = GetParam();
  const std::string p = data_path(std::string("spd/") + c.file);
  SKIP_IF_ABSENT(p);
  Scene s = load_nff(p);
  const Geometry* round_cones = find_geom(s, PrimType::RoundCone);
  const Geometry* spheres = find_geom(s, PrimType::Sphere);
  const Geometry* tris = find_geom(s, PrimType::Triangle);
  ASSERT_TRUE(round_cones && spheres && tris);
  EXPECT_EQ(round_cones->round_cones.size(), c.round_cones);
  EXPECT_EQ(spheres->spheres.size(), c.spheres);
  // One 4-vertex polygon (the floor / back plane) in each file -> 2 triangles.
  EXPECT_EQ(tris->vertices.size(), 4u);
  EXPECT_EQ(tris->triangles.size(), 2u);
  EXPECT_EQ(s.instances.size(), s.geometries.size());
  EXPECT_EQ(s.camera.fov_y_deg, 45.0);
  EXPECT_EQ(s.camera.up, glm::dvec3(0, 0, 1));
  EXPECT_NO_THROW(validate_scene(s));
}

INSTANTIATE_TEST_SUITE_P(Spd, NffReal,
                         ::testing::Values(SpdCase{"rings_sf7.nff", 4200, 4200}, SpdCase{"rings_sf13.nff", 24570, 24570},
                                           SpdCase{"tree_sf11.nff", 4095, 4095}, SpdCase{"tree_sf14.nff", 32767, 32767}),
                         [](const auto& param_info) {
                           std::string n = param_info.param.file;
                           return n.substr(0, n.find('.'));
                         });

TEST(NffReal, TreeCameraAndFirstCone) {
  const std::string p = data_path("spd/tree_sf11.nff");
  SKIP_IF_ABSENT(p);
  Scene s = load_nff(p);
  EXPECT_EQ(s.camera.eye, glm::dvec3(4.5, 0.4, 2));
  EXPECT_EQ(s.camera.target, glm::dvec3(0, 0, 1.5));
  const RoundConePrim& c = find_geom(s, PrimType::RoundCone)->round_cones[0];  // c 0 0 0 0.15 0 0 1 0.1005
  EXPECT_EQ(c.a, glm::vec3(0, 0, 0));
  EXPECT_FLOAT_EQ(c.ra, 0.15f);
  EXPECT_EQ(c.b, glm::vec3(0, 0, 1));
  EXPECT_FLOAT_EQ(c.rb, 0.1005f);
}

// ================= PLY

TEST(Ply, AsciiFanTriangulation) {
  Scene s = ply(write_ply(kVerts, kFaces, "ascii"));
  ASSERT_EQ(s.geometries.size(), 1u);
  const Geometry& g = s.geometries[0];
  EXPECT_EQ(g.vertices.size(), 5u);
  ASSERT_EQ(g.triangles.size(), 2u + 1u + 1u + 3u);
  EXPECT_EQ(g.triangles[0], glm::uvec3(0, 1, 2));
  EXPECT_EQ(g.triangles[1], glm::uvec3(0, 2, 3));
  EXPECT_EQ(g.triangles[6], glm::uvec3(2, 0, 1));
}

TEST(Ply, BinaryEqualsAscii) {
  Scene a = ply(write_ply(kVerts, kFaces, "ascii"));
  for (const char* fmt : {"binary_little_endian", "binary_big_endian"}) {
    SCOPED_TRACE(fmt);
    Scene b = ply(write_ply(kVerts, kFaces, fmt));
    ASSERT_EQ(b.geometries.size(), 1u);
    EXPECT_EQ(b.geometries[0].vertices, a.geometries[0].vertices);
    EXPECT_EQ(b.geometries[0].triangles, a.geometries[0].triangles);
  }
}

TEST(Ply, BinaryDoubleAndCrlfHeader) {
  std::string h = "ply\r\nformat binary_little_endian 1.0\r\nelement vertex 3\r\nproperty double x\r\nproperty double y\r\n"
                  "property double z\r\nelement face 1\r\nproperty list uint8 uint32 vertex_index\r\nend_header\r\n";
  std::vector<std::byte> b = bytes_of(h);
  for (double v : {0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 2.0, 0.0}) put(b, v, false);
  put(b, static_cast<unsigned char>(3), false);
  for (std::uint32_t i : {0u, 1u, 2u}) put(b, i, false);
  Scene s = ply(b);
  ASSERT_EQ(s.geometries[0].triangles.size(), 1u);
  EXPECT_EQ(s.geometries[0].vertices[2], glm::vec3(0, 2, 0));
}

const char* kStrandPly =
    "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
    "property float radius\nelement edge 2\nproperty int vertex1\nproperty int vertex2\nend_header\n"
    "0 0 0 0.1\n1 0 0 0.2\n2 0 0 0.4\n0 1\n1 2\n";

TEST(Ply, EdgesToCapsules) {
  Scene s = ply(kStrandPly);
  ASSERT_EQ(s.geometries.size(), 1u);
  const Geometry& g = s.geometries[0];
  ASSERT_EQ(g.type, PrimType::Capsule);
  ASSERT_EQ(g.capsules.size(), 2u);
  EXPECT_EQ(g.capsules[1].a, glm::vec3(1, 0, 0));
  EXPECT_EQ(g.capsules[1].b, glm::vec3(2, 0, 0));
  EXPECT_FLOAT_EQ(g.capsules[0].radius, 0.15f);
  EXPECT_FLOAT_EQ(g.capsules[1].radius, 0.3f);
}

TEST(Ply, EdgesToRoundCones) {
  LoadOptions o;
  o.strand_type = PrimType::RoundCone;
  Scene s = ply(kStrandPly, o);
  const Geometry& g = s.geometries[0];
  ASSERT_EQ(g.type, PrimType::RoundCone);
  ASSERT_EQ(g.round_cones.size(), 2u);
  EXPECT_FLOAT_EQ(g.round_cones[1].ra, 0.2f);
  EXPECT_FLOAT_EQ(g.round_cones[1].rb, 0.4f);
}

TEST(Ply, EdgeRadiusFromOptionsOrDefault) {
  const std::string f = "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\nproperty float z\n"
                        "element edge 1\nproperty uint vertex1\nproperty uint vertex2\nend_header\n0 0 0\n10 0 0\n0 1\n";
  LoadOptions o;
  o.radius = 0.25f;
  EXPECT_FLOAT_EQ(ply(f, o).geometries[0].capsules[0].radius, 0.25f);
  EXPECT_FLOAT_EQ(ply(f).geometries[0].capsules[0].radius, 0.02f);  // 0.002 x bbox diagonal 10
}

// ---- PLY bad input, one per class

TEST(PlyBad, WrongMagic) {
  expect_error([] { ply("plx\nformat ascii 1.0\nend_header\n"); }, {"test.ply", "line 1", "PLY"});
  expect_error([] { ply(""); }, {"test.ply", "line 1"});
}

TEST(PlyBad, UnknownFormatAndType) {
  expect_error([] { ply("ply\nformat binary_middle_endian 1.0\nend_header\n"); }, {"line 2", "binary_middle_endian"});
  expect_error([] { ply("ply\nformat ascii 1.0\nelement vertex 1\nproperty float128 x\nend_header\n"); },
               {"line 4", "float128"});
  expect_error([] { ply("ply\nformat ascii 1.0\nelement vertex 1\nbogus\nend_header\n"); }, {"line 4", "bogus"});
}

TEST(PlyBad, TruncatedHeader) {
  expect_error([] { ply("ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n"); }, {"test.ply", "line 5", "end_header"});
}

TEST(PlyBad, TruncatedAsciiBody) {
  std::vector<std::byte> b = write_ply(kVerts, kFaces, "ascii");
  b.resize(b.size() - 4);  // cut inside the last face
  expect_error([&] { ply(b); }, {"test.ply", "line 20", "face 3", "end of file"});
}

TEST(PlyBad, TruncatedBinaryBody) {
  for (const char* fmt : {"binary_little_endian", "binary_big_endian"}) {
    std::vector<std::byte> b = write_ply(kVerts, kFaces, fmt);
    b.resize(b.size() - 3);
    expect_error([&] { ply(b); }, {"test.ply", "offset "});
  }
}

TEST(PlyBad, CountExceedsFile) {
  // Binary: 4e9 vertices declared, a few bytes present: refused before any allocation.
  std::string h = "ply\nformat binary_little_endian 1.0\nelement vertex 4000000000\nproperty float x\nproperty float y\n"
                  "property float z\nelement face 0\nproperty list uchar int vertex_indices\nend_header\n";
  const std::size_t header = h.size();
  expect_error([&] { ply(h + "abcdefgh"); }, {"test.ply", "offset " + std::to_string(header), "element vertex"});
  // A list count beyond the file.
  std::vector<std::byte> b = bytes_of("ply\nformat binary_big_endian 1.0\nelement face 1\nproperty list uint int vertex_indices\n"
                                      "element vertex 0\nproperty float x\nproperty float y\nproperty float z\nend_header\n");
  put(b, static_cast<std::uint32_t>(0xffffffffu), true);
  expect_error([&] { ply(b); }, {"offset "});
  // ASCII: count larger than the lines present.
  expect_error([] { ply("ply\nformat ascii 1.0\nelement vertex 99999999999\nproperty float x\nproperty float y\nproperty float z\n"
                        "element face 0\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 1 1\n"); },
               {"line 12", "end of file"});
}

TEST(PlyBad, FaceIndexOutOfRange) {
  std::vector<std::vector<int>> faces = {{0, 1, 2}, {0, 1, 5}};
  expect_error([&] { ply(write_ply(kVerts, faces, "ascii")); }, {"test.ply", "line 18", "vertex index 5 out of range"});
  faces = {{0, 1, 2}, {-1, 1, 2}};
  expect_error([&] { ply(write_ply(kVerts, faces, "binary_little_endian")); }, {"test.ply", "offset ", "out of range"});
}

TEST(PlyBad, NonFiniteCoordinate) {
  std::vector<PlyVertex> vs = kVerts;
  vs[2].y = std::numeric_limits<float>::quiet_NaN();
  expect_error([&] { ply(write_ply(vs, kFaces, "binary_big_endian")); }, {"test.ply", "offset ", "vertex 2", "finite"});
  vs[2].y = 0;
  vs[3].z = std::numeric_limits<float>::infinity();
  expect_error([&] { ply(write_ply(vs, kFaces, "ascii")); }, {"test.ply", "line 15", "vertex 3", "finite"});
}

TEST(PlyBad, NegativeRadiusRepaired) {
  std::string f = kStrandPly;
  f.replace(f.find("0.2"), 3, "-0.2");
  std::vector<std::string> warnings;
  LoadOptions o;
  o.warn = [&](const std::string& w) { warnings.push_back(w); };
  Scene s = ply(f, o);
  EXPECT_FLOAT_EQ(s.geometries[0].capsules[0].radius, 0.15f);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("line 13"), std::string::npos) << warnings[0];
  EXPECT_NE(warnings[0].find("negative radius"), std::string::npos) << warnings[0];
}

TEST(PlyBad, PolygonTooSmall) {
  std::vector<std::vector<int>> faces = {{0, 1, 2}, {0, 1}};
  expect_error([&] { ply(write_ply(kVerts, faces, "ascii")); }, {"test.ply", "line 18", "at least 3"});
  expect_error([&] { ply(write_ply(kVerts, faces, "binary_little_endian")); }, {"test.ply", "offset ", "at least 3"});
}

TEST(PlyBad, NotANumber) {
  std::vector<std::byte> b = write_ply(kVerts, kFaces, "ascii");
  std::string s(reinterpret_cast<const char*>(b.data()), b.size());
  s.replace(s.find("1.000000"), 8, "1.0x0000");
  expect_error([&] { ply(s); }, {"line 13", "not a number"});
}

TEST(PlyBad, MissingFile) { expect_error([] { load_ply("/nonexistent/x.ply"); }, {"/nonexistent/x.ply", "cannot open"}); }

// ================= NFF

TEST(Nff, OneAndThreeLineConesAgree) {
  Scene one = nff("c 0 0 0 0.5 0 0 2 0.25\n");
  Scene three = nff("c\n0 0 0 0.5\n0 0 2 0.25\n");
  ASSERT_EQ(three.geometries.size(), 1u);
  ASSERT_EQ(three.geometries[0].round_cones.size(), 1u);
  const RoundConePrim& a = one.geometries[0].round_cones[0];
  const RoundConePrim& b = three.geometries[0].round_cones[0];
  EXPECT_EQ(a.a, b.a);
  EXPECT_EQ(a.b, b.b);
  EXPECT_EQ(b.b, glm::vec3(0, 0, 2));
  EXPECT_FLOAT_EQ(b.ra, 0.5f);
  EXPECT_FLOAT_EQ(b.rb, 0.25f);
}

TEST(Nff, MixedScene) {
  Scene s = nff("# comment\nv\nfrom 1 2 3\nat 0 0 0\nup 0 1 0\nangle 30\nhither 0.1\nresolution 64 48\n"
                "b 0 0 0\nl 1 1 1\nl 1 1 1 0.5 0.5 0.5\nf 1 0 0 0.5 0.5 3 0 1\n"
                "s 1 1 1 0.5\nc\n0 0 0 1\n0 1 0 1\npp 3\n0 0 0 0 0 1\n1 0 0 0 0 1\n0 1 0 0 0 1\np 5\n0 0 0\n1 0 0\n1 1 0\n0.5 2 0\n0 1 0\n");
  ASSERT_EQ(s.geometries.size(), 3u);
  EXPECT_EQ(s.geometries[0].type, PrimType::Sphere);
  EXPECT_EQ(s.geometries[1].type, PrimType::RoundCone);
  EXPECT_EQ(s.geometries[2].type, PrimType::Triangle);
  EXPECT_EQ(s.geometries[2].vertices.size(), 8u);
  EXPECT_EQ(s.geometries[2].triangles.size(), 1u + 3u);
  EXPECT_EQ(s.geometries[2].triangles[1], glm::uvec3(3, 4, 5));
  EXPECT_EQ(s.instances.size(), 3u);
  EXPECT_EQ(s.camera.eye, glm::dvec3(1, 2, 3));
  EXPECT_EQ(s.camera.fov_y_deg, 30.0);
  EXPECT_NO_THROW(validate_scene(s));
}

TEST(NffBad, Truncated) {
  expect_error([] { nff("s 0 0 0 1\nc 0 0 0 1\n0 0"); }, {"test.nff", "line 2", "end of file"});
  // A polygon count larger than the file: fails at the end, nothing sized from the count.
  expect_error([] { nff("p 4000000000\n0 0 0\n1 0 0\n"); }, {"test.nff", "line 1", "end of file"});
}

TEST(NffBad, UnknownKeyword) { expect_error([] { nff("s 0 0 0 1\n\ncube 1 2 3\n"); }, {"test.nff", "line 3", "cube"}); }

TEST(NffBad, NotANumber) {
  expect_error([] { nff("s 0 0 0 1\ns 0 zero 0 1\n"); }, {"test.nff", "line 2", "'zero'"});
  expect_error([] { nff("s 0 0 0 1\nf 1 x 0\n"); }, {"test.nff", "line 2", "'x'"});
}

TEST(NffBad, NonFinite) {
  expect_error([] { nff("s 0 0 0 1\nc\n0 0 0 1\n0 nan 0 1\n"); }, {"test.nff", "line 4", "finite"});
  expect_error([] { nff("p 3\n0 0 0\n1 inf 0\n0 1 0\n"); }, {"test.nff", "line 3", "finite"});
  expect_error([] { nff("s 0 0 0 1e300\n"); }, {"test.nff", "line 1", "finite"});
}

TEST(NffBad, NegativeRadiusRepaired) {
  std::vector<std::string> warnings;
  LoadOptions o;
  o.warn = [&](const std::string& w) { warnings.push_back(w); };
  Scene s = nff("s 0 0 0 1\ns 1 1 1 -2\n", o);
  EXPECT_FLOAT_EQ(s.geometries[0].spheres[1].radius, 2.0f);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("line 2"), std::string::npos) << warnings[0];
}

TEST(NffBad, PolygonTooSmall) {
  expect_error([] { nff("s 0 0 0 1\np 2\n0 0 0\n1 0 0\n"); }, {"test.nff", "line 2", ">= 3"});
  expect_error([] { nff("p 3.5\n"); }, {"test.nff", "line 1"});
}

TEST(NffBad, Empty) { expect_error([] { nff("v\nfrom 0 0 1\n"); }, {"test.nff", "no primitives"}); }
