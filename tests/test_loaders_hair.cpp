// TressFX (.tfx) and Cem Yuksel .hair loaders: real files, round trips, bad input.
#include "masq/error.h"
#include "scenes/loaders/load_hair.h"
#include "scenes/loaders/load_tressfx.h"
#include <gtest/gtest.h>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <limits>

using namespace masq;

namespace {

std::string hair_dir() { return std::string(MASQ_DATA_DIR) + "/hair"; }

#define REQUIRE_DATA()                                                                              \
  do {                                                                                              \
    if (!std::filesystem::is_directory(hair_dir()))                                                 \
      GTEST_SKIP() << "real hair data not found at " << hair_dir()                                  \
                   << " (configure with -DMASQ_DEFAULT_DATA_DIR=<shared/data>)";                    \
  } while (0)

template <class F>
std::string error_of(F&& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  } catch (const std::exception& e) {
    ADD_FAILURE() << "not a masq::Error: " << e.what();
    return {};
  }
  ADD_FAILURE() << "no error thrown";
  return {};
}

bool same_prims(const Geometry& a, const Geometry& b) {
  if (a.type != b.type || a.capsules.size() != b.capsules.size() || a.round_cones.size() != b.round_cones.size()) return false;
  if (!a.capsules.empty() && std::memcmp(a.capsules.data(), b.capsules.data(), a.capsules.size() * sizeof(CapsulePrim)))
    return false;
  if (!a.round_cones.empty() && std::memcmp(a.round_cones.data(), b.round_cones.data(), a.round_cones.size() * sizeof(RoundConePrim)))
    return false;
  return true;
}

struct TfxCase {
  const char* file;
  std::size_t strands;
  std::size_t verts;
};

// Loads a real file from the path and from memory (capsules and round cones) and checks
// the counts, the strand structure and that the two routes agree bit for bit.
void check_tfx(const TfxCase& c) {
  SCOPED_TRACE(c.file);
  const std::string path = hair_dir() + "/" + c.file;
  std::vector<std::string> warnings;
  LoadOptions opt;
  opt.warn = [&](const std::string& w) { warnings.push_back(w); };
  Scene s = load_tressfx(path, opt);
  ASSERT_EQ(s.geometries.size(), 1u);
  ASSERT_EQ(s.instances.size(), 1u);
  const Geometry& g = s.geometries[0];
  EXPECT_EQ(g.type, PrimType::Capsule);
  ASSERT_EQ(g.capsules.size(), c.strands * (c.verts - 1));
  ASSERT_FALSE(warnings.empty()); // no thickness in these files: the default radius is reported
  EXPECT_NE(warnings[0].find("radius"), std::string::npos);
  const float r0 = g.capsules[0].radius;
  EXPECT_GT(r0, 0.0f);
  for (std::size_t i = 0; i < g.capsules.size(); ++i) {
    ASSERT_EQ(g.capsules[i].radius, r0);
    if ((i + 1) % (c.verts - 1) != 0) {
      ASSERT_EQ(g.capsules[i].b, g.capsules[i + 1].a) << "segment " << i;
    }
  }
  EXPECT_NO_THROW(validate_scene(s));

  std::vector<std::byte> bytes = read_file_bytes(path);
  Scene m = load_tressfx(bytes, path, opt);
  EXPECT_TRUE(same_prims(s.geometries[0], m.geometries[0]));

  LoadOptions cone;
  cone.strand_type = PrimType::RoundCone;
  cone.radius = 0.25f;
  Scene k = load_tressfx(bytes, path, cone);
  const Geometry& gk = k.geometries[0];
  EXPECT_EQ(gk.type, PrimType::RoundCone);
  ASSERT_EQ(gk.round_cones.size(), g.capsules.size());
  for (std::size_t i = 0; i < gk.round_cones.size(); ++i) {
    ASSERT_EQ(gk.round_cones[i].a, g.capsules[i].a);
    ASSERT_EQ(gk.round_cones[i].b, g.capsules[i].b);
    ASSERT_EQ(gk.round_cones[i].ra, 0.25f);
    ASSERT_EQ(gk.round_cones[i].rb, 0.25f);
  }
}

} // namespace

TEST(TressFX, Bear) {
  REQUIRE_DATA();
  check_tfx({"tressfx3_bear.tfx", 48113, 4});
  EXPECT_EQ(load_tressfx(hair_dir() + "/tressfx3_bear.tfx").primitive_count(), 144339u);
}

TEST(TressFX, PonytailParts) {
  REQUIRE_DATA();
  std::size_t total = 0;
  const std::pair<const char*, std::size_t> parts[] = {{"tressfx3_ponytail_back.tfx", 517},
                                                       {"tressfx3_ponytail_front_top.tfx", 876},
                                                       {"tressfx3_ponytail_side.tfx", 3066},
                                                       {"tressfx3_ponytail_tail.tfx", 474}};
  for (auto [f, n] : parts) {
    check_tfx({f, n, 16});
    total += load_tressfx(hair_dir() + "/" + f).primitive_count();
  }
  EXPECT_EQ(total, 73995u);
}

TEST(TressFX, TestHair1) {
  REQUIRE_DATA();
  check_tfx({"tressfx3_TestHair1.tfx", 10027, 4});
}

TEST(TressFX, RatboyV4) {
  REQUIRE_DATA();
  check_tfx({"tressfx4_Ratboy_mohawk.tfx", 2228, 32});
  EXPECT_EQ(load_tressfx(hair_dir() + "/tressfx4_Ratboy_mohawk.tfx").primitive_count(), 69068u);
}

TEST(TressFX, SintelV4) {
  REQUIRE_DATA();
  check_tfx({"tressfx4_sintel_hair.tfx", 228, 32});
}

TEST(TressFX, MissingFile) {
  std::string e = error_of([] { load_tressfx("/nonexistent/dir/x.tfx"); });
  EXPECT_NE(e.find("/nonexistent/dir/x.tfx"), std::string::npos) << e;
}

// ---- handmade TressFX buffers -------------------------------------------------------

namespace {

template <class T>
void poke(std::vector<std::byte>& b, std::size_t off, T v) {
  std::memcpy(b.data() + off, &v, sizeof v);
}

// A valid file: `strands` strands of `vps` vertices, vertex (s, v) at (s, v, 0.5 s).
std::vector<std::byte> make_tfx(int version, std::uint32_t strands, std::uint32_t vps, bool thickness = false) {
  const std::size_t header = version == 3 ? 296 : 160;
  const std::size_t stride = version == 3 ? 12 : 16;
  const std::size_t pos = header, thick = pos + std::size_t(strands) * vps * stride;
  std::vector<std::byte> b(thick + (thickness ? strands * 4 : 0));
  poke(b, 0, float(version));
  poke(b, 4, strands);
  poke(b, 8, vps);
  poke(b, version == 3 ? 144 : 12, std::uint32_t(pos));
  if (thickness) poke(b, version == 3 ? 148 : 24, std::uint32_t(thick));
  for (std::uint32_t s = 0; s < strands; ++s) {
    for (std::uint32_t v = 0; v < vps; ++v) {
      const std::size_t o = pos + (std::size_t(s) * vps + v) * stride;
      poke(b, o, float(s)), poke(b, o + 4, float(v)), poke(b, o + 8, 0.5f * float(s));
      if (stride == 16) poke(b, o + 12, 1.0f);
    }
    if (thickness) poke(b, thick + s * 4, 0.5f + float(s));
  }
  return b;
}

} // namespace

TEST(TressFX, HandmadeValid) {
  for (int version : {3, 4}) {
    SCOPED_TRACE(version);
    LoadOptions opt;
    opt.radius = 2.0f;
    Scene s = load_tressfx(make_tfx(version, 3, 5), "mem", opt);
    ASSERT_EQ(s.primitive_count(), 12u);
    const auto& c = s.geometries[0].capsules;
    EXPECT_EQ(c[4].a, glm::vec3(1, 0, 0.5f));
    EXPECT_EQ(c[4].b, glm::vec3(1, 1, 0.5f));
    EXPECT_EQ(c[4].radius, 2.0f);
    // Thickness array: a per-strand coefficient on the base radius.
    Scene t = load_tressfx(make_tfx(version, 3, 5, true), "mem", opt);
    EXPECT_EQ(t.geometries[0].capsules[0].radius, 1.0f);
    EXPECT_EQ(t.geometries[0].capsules[11].radius, 5.0f);
  }
}

TEST(TressFX, Truncated) {
  for (int version : {3, 4}) {
    SCOPED_TRACE(version);
    auto b = make_tfx(version, 3, 5);
    auto head = std::vector<std::byte>(b.begin(), b.begin() + 100);
    std::string e = error_of([&] { load_tressfx(head, "cut.tfx"); });
    EXPECT_NE(e.find("cut.tfx: offset 0"), std::string::npos) << e;
    b.resize(b.size() - 5);
    const std::string pos = version == 3 ? "offset 296" : "offset 160";
    e = error_of([&] { load_tressfx(b, "cut.tfx"); });
    EXPECT_NE(e.find(pos), std::string::npos) << e;
    e = error_of([] { load_tressfx(std::span<const std::byte>{}, "empty.tfx"); });
    EXPECT_NE(e.find("empty.tfx: offset 0"), std::string::npos) << e;
  }
}

TEST(TressFX, WrongVersion) {
  for (float v : {2.0f, 5.0f, std::numeric_limits<float>::quiet_NaN(), -3.0f}) {
    auto b = make_tfx(3, 2, 4);
    poke(b, 0, v);
    std::string e = error_of([&] { load_tressfx(b, "v.tfx"); });
    EXPECT_NE(e.find("v.tfx: offset 0"), std::string::npos) << e;
    EXPECT_NE(e.find("version"), std::string::npos) << e;
  }
}

TEST(TressFX, CountsExceedFile) {
  for (int version : {3, 4}) {
    SCOPED_TRACE(version);
    auto b = make_tfx(version, 2, 4);
    poke(b, 4, std::uint32_t(0xFFFFFFF0u));
    std::string e = error_of([&] { load_tressfx(b, "n.tfx"); });
    EXPECT_NE(e.find(version == 3 ? "offset 296" : "offset 160"), std::string::npos) << e;
    b = make_tfx(version, 2, 4);
    poke(b, 8, std::uint32_t(0xFFFFFFFFu));
    e = error_of([&] { load_tressfx(b, "n.tfx"); });
    EXPECT_NE(e.find("offset"), std::string::npos) << e;
    b = make_tfx(version, 2, 4);
    poke(b, 8, std::uint32_t(1));
    e = error_of([&] { load_tressfx(b, "n.tfx"); });
    EXPECT_NE(e.find("n.tfx: offset 8"), std::string::npos) << e;
  }
}

TEST(TressFX, OffsetsOutsideFile) {
  for (int version : {3, 4}) {
    SCOPED_TRACE(version);
    const std::size_t field = version == 3 ? 144 : 12;
    auto b = make_tfx(version, 2, 4);
    poke(b, field, std::uint32_t(1000000));
    std::string e = error_of([&] { load_tressfx(b, "o.tfx"); });
    EXPECT_NE(e.find("o.tfx: offset " + std::to_string(field)), std::string::npos) << e;
    poke(b, field, std::uint32_t(8)); // into the header
    e = error_of([&] { load_tressfx(b, "o.tfx"); });
    EXPECT_NE(e.find("offset " + std::to_string(field)), std::string::npos) << e;
    poke(b, field, std::uint32_t(0));
    e = error_of([&] { load_tressfx(b, "o.tfx"); });
    EXPECT_NE(e.find("offset " + std::to_string(field)), std::string::npos) << e;
    // Positions that start inside the file but run past its end.
    poke(b, field, std::uint32_t(b.size() - 20));
    e = error_of([&] { load_tressfx(b, "o.tfx"); });
    EXPECT_NE(e.find("offset " + std::to_string(b.size() - 20)), std::string::npos) << e;
    // Thickness offset outside the file.
    b = make_tfx(version, 2, 4);
    const std::size_t tfield = version == 3 ? 148 : 24;
    poke(b, tfield, std::uint32_t(0x7FFFFFFF));
    e = error_of([&] { load_tressfx(b, "o.tfx"); });
    EXPECT_NE(e.find("offset " + std::to_string(tfield)), std::string::npos) << e;
  }
}

TEST(TressFX, NonFiniteCoordinate) {
  for (int version : {3, 4}) {
    SCOPED_TRACE(version);
    const std::size_t header = version == 3 ? 296 : 160, stride = version == 3 ? 12 : 16;
    auto b = make_tfx(version, 3, 5);
    const std::size_t off = header + (1 * 5 + 2) * stride + 4;
    poke(b, off, std::numeric_limits<float>::quiet_NaN());
    std::string e = error_of([&] { load_tressfx(b, "nan.tfx"); });
    EXPECT_NE(e.find("strand 1 vertex 2"), std::string::npos) << e;
    EXPECT_NE(e.find("offset " + std::to_string(off - 4)), std::string::npos) << e;
    poke(b, off, std::numeric_limits<float>::infinity());
    e = error_of([&] { load_tressfx(b, "inf.tfx"); });
    EXPECT_NE(e.find("strand 1 vertex 2"), std::string::npos) << e;
  }
}

TEST(TressFX, NegativeThicknessRepaired) {
  for (int version : {3, 4}) {
    SCOPED_TRACE(version);
    auto b = make_tfx(version, 3, 5, true);
    const std::size_t thick = (version == 3 ? 296 : 160) + 15 * std::size_t(version == 3 ? 12 : 16);
    poke(b, thick + 4, -1.5f);
    std::vector<std::string> warnings;
    LoadOptions opt;
    opt.radius = 1.0f;
    opt.warn = [&](const std::string& w) { warnings.push_back(w); };
    Scene s = load_tressfx(b, "neg.tfx", opt);
    EXPECT_EQ(s.geometries[0].capsules[4].radius, 1.5f);
    ASSERT_EQ(warnings.size(), 1u);
    EXPECT_NE(warnings[0].find("offset " + std::to_string(thick + 4)), std::string::npos) << warnings[0];
    poke(b, thick + 4, std::numeric_limits<float>::quiet_NaN());
    std::string e = error_of([&] { load_tressfx(b, "nan.tfx", opt); });
    EXPECT_NE(e.find("offset " + std::to_string(thick + 4)), std::string::npos) << e;
  }
}

TEST(TressFX, ZeroStrands) {
  for (int version : {3, 4}) {
    auto b = make_tfx(version, 2, 4);
    poke(b, 4, std::uint32_t(0));
    std::string e = error_of([&] { load_tressfx(b, "z.tfx"); });
    EXPECT_NE(e.find("z.tfx: offset 4"), std::string::npos) << e;
  }
}

TEST(TressFX, BadStrandType) {
  LoadOptions opt;
  opt.strand_type = PrimType::Triangle;
  std::string e = error_of([&] { load_tressfx(make_tfx(3, 2, 4), "t.tfx", opt); });
  EXPECT_NE(e.find("t.tfx"), std::string::npos) << e;
}

// ---- .hair ---------------------------------------------------------------------------

namespace {

// Strands of `segs[i]` segments with radius r(strand, point).
template <class R>
Scene strands(PrimType type, const std::vector<int>& segs, R r) {
  Geometry g;
  g.type = type;
  for (std::size_t s = 0; s < segs.size(); ++s) {
    for (int k = 0; k < segs[s]; ++k) {
      glm::vec3 a(float(s) * 1.25f, 0.1f * float(k), std::sin(float(k + s)));
      glm::vec3 b(float(s) * 1.25f, 0.1f * float(k + 1), std::sin(float(k + 1 + s)));
      if (type == PrimType::Capsule) g.capsules.push_back({a, b, r(s, k)});
      else g.round_cones.push_back({a, r(s, k), b, r(s, k + 1)});
    }
  }
  return scene_of(std::move(g), "strands");
}

std::uint32_t flags_of(const std::vector<std::byte>& b) {
  std::uint32_t f;
  std::memcpy(&f, b.data() + 12, 4);
  return f;
}

void round_trip(const Scene& s, std::uint32_t expect_flags) {
  std::vector<std::byte> bytes = write_hair(s);
  EXPECT_EQ(flags_of(bytes), expect_flags);
  LoadOptions opt;
  opt.strand_type = s.geometries[0].type;
  int warned = 0;
  opt.warn = [&](const std::string&) { ++warned; };
  Scene back = load_hair(bytes, "rt.hair", opt);
  EXPECT_EQ(warned, 0);
  ASSERT_EQ(back.geometries.size(), 1u);
  EXPECT_TRUE(same_prims(s.geometries[0], back.geometries[0]));
  EXPECT_EQ(write_hair(back), bytes);
}

} // namespace

TEST(Hair, RoundTripNoArrays) {
  round_trip(strands(PrimType::Capsule, {4, 4, 4}, [](std::size_t, int) { return 0.125f; }), 2u);
  round_trip(strands(PrimType::RoundCone, {7, 7}, [](std::size_t, int) { return 0.3f; }), 2u);
}

TEST(Hair, RoundTripSegmentsArray) {
  round_trip(strands(PrimType::Capsule, {1, 4, 9, 2}, [](std::size_t, int) { return 0.7f; }), 3u);
}

TEST(Hair, RoundTripThicknessArray) {
  // Capsules with a radius per strand (and one of zero radius).
  round_trip(strands(PrimType::Capsule, {3, 3, 3}, [](std::size_t s, int) { return 0.1f * float(s); }), 6u);
  // Round cones with radii varying along each strand, and varying segment counts.
  round_trip(strands(PrimType::RoundCone, {5, 2, 11},
                     [](std::size_t s, int k) { return 0.01f + 0.37f * float(k) / float(s + 3); }),
             7u);
}

TEST(Hair, CapsuleRadiusChangeSplitsStrand) {
  // Radii changing along a capsule strand: written as separate strands (six of one
  // segment each, so no segments array), read back exactly.
  Scene s = strands(PrimType::Capsule, {6}, [](std::size_t, int k) { return 0.5f + float(k); });
  round_trip(s, 6u);
  std::uint32_t n;
  std::memcpy(&n, write_hair(s).data() + 4, 4);
  EXPECT_EQ(n, 6u);
}

TEST(Hair, ConeReadAsCapsuleUsesMeanRadius) {
  Scene s = strands(PrimType::RoundCone, {3}, [](std::size_t, int k) { return 1.0f + float(k); });
  Scene c = load_hair(write_hair(s), "m.hair");
  ASSERT_EQ(c.geometries[0].capsules.size(), 3u);
  EXPECT_EQ(c.geometries[0].capsules[0].radius, 1.5f);
  EXPECT_EQ(c.geometries[0].capsules[2].radius, 3.5f);
}

TEST(Hair, PathAndMemoryAgree) {
  Scene s = strands(PrimType::RoundCone, {5, 2, 11}, [](std::size_t s_, int k) { return 0.02f * float(k + s_ + 1); });
  const std::string path = ::testing::TempDir() + "masq_test_loaders_hair.hair";
  save_hair(s, path);
  LoadOptions opt;
  opt.strand_type = PrimType::RoundCone;
  Scene a = load_hair(path, opt);
  Scene b = load_hair(read_file_bytes(path), path, opt);
  EXPECT_TRUE(same_prims(a.geometries[0], b.geometries[0]));
  EXPECT_TRUE(same_prims(a.geometries[0], s.geometries[0]));
  EXPECT_EQ(a.name, b.name);
  std::filesystem::remove(path);
}

TEST(Hair, WriterRejectsOtherContent) {
  Scene sph;
  Geometry g;
  g.type = PrimType::Sphere;
  g.spheres.push_back({{0, 0, 0}, 1});
  sph = scene_of(g, "sph");
  EXPECT_NE(error_of([&] { write_hair(sph); }).find("sphere"), std::string::npos);
  Scene moved = strands(PrimType::Capsule, {2}, [](std::size_t, int) { return 1.0f; });
  moved.instances[0].object_to_world.translation = {1, 0, 0};
  EXPECT_NE(error_of([&] { write_hair(moved); }).find("instance 0"), std::string::npos);
  Scene empty;
  error_of([&] { write_hair(empty); });
}

TEST(Hair, DefaultRadiusWhenNoThickness) {
  auto b = write_hair(strands(PrimType::Capsule, {2, 2}, [](std::size_t, int) { return 1.0f; }));
  poke(b, 20, 0.0f); // default thickness 0 and no array
  std::vector<std::string> warnings;
  LoadOptions opt;
  opt.warn = [&](const std::string& w) { warnings.push_back(w); };
  Scene s = load_hair(b, "d.hair", opt);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_GT(s.geometries[0].capsules[0].radius, 0.0f);
  opt.radius = 0.75f;
  warnings.clear();
  s = load_hair(b, "d.hair", opt);
  EXPECT_TRUE(warnings.empty());
  EXPECT_EQ(s.geometries[0].capsules[0].radius, 0.75f);
}

namespace {
// 3 strands of 1, 4 and 2 segments (segments array) with a thickness array.
std::vector<std::byte> hair_with_arrays() {
  auto b = write_hair(strands(PrimType::RoundCone, {1, 4, 2}, [](std::size_t s, int k) { return 0.1f * float(s + k + 1); }));
  EXPECT_EQ(flags_of(b), 7u);
  return b;
}
constexpr std::size_t kPts = 128 + 3 * 2;  // points array offset in hair_with_arrays()
constexpr std::size_t kThick = kPts + 10 * 12;
} // namespace

TEST(Hair, Truncated) {
  auto b = hair_with_arrays();
  ASSERT_EQ(b.size(), kThick + 10 * 4);
  std::vector<std::byte> head(b.begin(), b.begin() + 100);
  std::string e = error_of([&] { load_hair(head, "cut.hair"); });
  EXPECT_NE(e.find("cut.hair: offset 0"), std::string::npos) << e;
  std::vector<std::byte> pts(b.begin(), b.begin() + kPts + 50);
  e = error_of([&] { load_hair(pts, "cut.hair"); });
  EXPECT_NE(e.find("offset " + std::to_string(kPts)), std::string::npos) << e;
  b.pop_back();
  e = error_of([&] { load_hair(b, "cut.hair"); });
  EXPECT_NE(e.find("offset " + std::to_string(kThick)), std::string::npos) << e;
  e = error_of([] { load_hair(std::span<const std::byte>{}, "empty.hair"); });
  EXPECT_NE(e.find("empty.hair: offset 0"), std::string::npos) << e;
}

TEST(Hair, WrongMagic) {
  auto b = hair_with_arrays();
  b[1] = std::byte{'X'};
  std::string e = error_of([&] { load_hair(b, "m.hair"); });
  EXPECT_NE(e.find("m.hair: offset 0"), std::string::npos) << e;
  EXPECT_NE(e.find("HAIR"), std::string::npos) << e;
}

TEST(Hair, CountsExceedFile) {
  auto b = hair_with_arrays();
  poke(b, 8, std::uint32_t(0xFFFFFFFFu)); // points
  std::string e = error_of([&] { load_hair(b, "n.hair"); });
  EXPECT_NE(e.find("n.hair: offset " + std::to_string(kPts)), std::string::npos) << e;
  b = hair_with_arrays();
  poke(b, 4, std::uint32_t(0xFFFFFFFFu)); // strands (segments array)
  e = error_of([&] { load_hair(b, "n.hair"); });
  EXPECT_NE(e.find("n.hair: offset 128"), std::string::npos) << e;
  // Segments needing more points than the file has.
  b = hair_with_arrays();
  poke(b, 128 + 2, std::uint16_t(60000));
  e = error_of([&] { load_hair(b, "n.hair"); });
  EXPECT_NE(e.find("offset 130"), std::string::npos) << e;
  // Default segments (no segments array) too large, with many strands.
  b = write_hair(strands(PrimType::Capsule, {2, 2}, [](std::size_t, int) { return 1.0f; }));
  poke(b, 16, std::uint32_t(0xFFFFFFFFu));
  e = error_of([&] { load_hair(b, "n.hair"); });
  EXPECT_NE(e.find("offset 16"), std::string::npos) << e;
  poke(b, 16, std::uint32_t(0));
  poke(b, 4, std::uint32_t(0xFFFFFFFFu));
  e = error_of([&] { load_hair(b, "n.hair"); });
  EXPECT_NE(e.find("offset 16"), std::string::npos) << e;
}

TEST(Hair, NoPointsArray) {
  auto b = hair_with_arrays();
  poke(b, 12, std::uint32_t(5));
  std::string e = error_of([&] { load_hair(b, "p.hair"); });
  EXPECT_NE(e.find("p.hair: offset 12"), std::string::npos) << e;
}

TEST(Hair, NonFiniteCoordinate) {
  auto b = hair_with_arrays();
  const std::size_t off = kPts + 3 * 12; // strand 1 (points 2..6), point 1
  poke(b, off + 8, std::numeric_limits<float>::infinity());
  std::string e = error_of([&] { load_hair(b, "nan.hair"); });
  EXPECT_NE(e.find("strand 1 point 1"), std::string::npos) << e;
  EXPECT_NE(e.find("offset " + std::to_string(off)), std::string::npos) << e;
  b = hair_with_arrays();
  poke(b, kThick + 9 * 4, std::numeric_limits<float>::quiet_NaN());
  e = error_of([&] { load_hair(b, "nan.hair"); });
  EXPECT_NE(e.find("strand 2 point 2"), std::string::npos) << e;
  EXPECT_NE(e.find("offset " + std::to_string(kThick + 36)), std::string::npos) << e;
}

TEST(Hair, NegativeThicknessRepaired) {
  auto b = hair_with_arrays();
  poke(b, kThick + 4 * 4, -0.5f); // strand 1, point 2
  std::vector<std::string> warnings;
  LoadOptions opt;
  opt.strand_type = PrimType::RoundCone;
  opt.warn = [&](const std::string& w) { warnings.push_back(w); };
  Scene s = load_hair(b, "neg.hair", opt);
  EXPECT_EQ(s.geometries[0].round_cones[2].rb, 0.25f);
  EXPECT_EQ(s.geometries[0].round_cones[3].ra, 0.25f);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("offset " + std::to_string(kThick + 16)), std::string::npos) << warnings[0];
  EXPECT_NE(warnings[0].find("strand 1 point 2"), std::string::npos) << warnings[0];
}

TEST(Hair, ZeroStrands) {
  auto b = hair_with_arrays();
  poke(b, 4, std::uint32_t(0));
  std::string e = error_of([&] { load_hair(b, "z.hair"); });
  EXPECT_NE(e.find("z.hair: offset 4"), std::string::npos) << e;
}
