// The TrackVis .trk and MRtrix .tck loaders: the real .trk from MASQ_DATA_DIR, files
// built from the formats' byte layouts (either byte order, vox_to_ras, MRtrix's header
// rules), a .tck round trip, a .trk and a .tck of the same tracts overlaying, and one
// handmade broken input per error class.
#include "scenes/loaders/load_tracks.h"
#include "tests/loader_test_util.h"
#include <gtest/gtest.h>
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

using namespace masq;
using namespace masq::test;

namespace {
// ------------------------------------------------------------------------- TrackVis

// Writes a .trk from the TrackVis header layout: "TRACK", dim @6, voxel_size @12,
// n_scalars @36, n_properties @238, vox_to_ras @440, voxel_order @948, n_count @988,
// version @992, hdr_size @996, then per streamline i32 m and m*(3+n_scalars) f32 and
// n_properties f32, every number in one byte order (little-endian unless `big`).
class TrkWriter {
 public:
  explicit TrkWriter(std::int16_t n_scalars = 0, std::int16_t n_properties = 0, bool big = false)
      : b_(1000, std::byte{0}), big_(big) {
    std::memcpy(b_.data(), "TRACK", 6);
    put<std::int16_t>(36, n_scalars);
    put<std::int16_t>(238, n_properties);
    put<std::int32_t>(992, 2);
    put<std::int32_t>(996, 1000);
    ns_ = n_scalars;
    np_ = n_properties;
  }
  template <class T>
  void put(std::size_t off, T v) {
    unsigned char raw[sizeof(T)];
    std::memcpy(raw, &v, sizeof v);
    if (big_) std::reverse(raw, raw + sizeof(T));
    std::memcpy(b_.data() + off, raw, sizeof v);
  }
  template <class T>
  void append(T v) {
    std::size_t o = b_.size();
    b_.resize(o + sizeof v);
    put(o, v);
  }
  // A version-2 header's space: vox_to_ras (rows 0-2; row 3 is 0 0 0 1), voxel_size,
  // voxel_order (up to 4 characters) and dim.
  void space(const double (&v2r)[3][4], glm::vec3 voxel_size, const char* order, glm::ivec3 dim = {0, 0, 0}) {
    for (int row = 0; row < 4; ++row)
      for (int col = 0; col < 4; ++col)
        put<float>(440 + 4 * (4 * row + col), row < 3 ? static_cast<float>(v2r[row][col]) : (col == 3 ? 1.0f : 0.0f));
    for (int i = 0; i < 3; ++i) {
      put<float>(12 + 4 * i, voxel_size[i]);
      put<std::int16_t>(6 + 2 * i, static_cast<std::int16_t>(dim[i]));
    }
    std::memset(b_.data() + 948, 0, 4);
    std::memcpy(b_.data() + 948, order, std::min<std::size_t>(4, std::strlen(order)));
  }
  void streamline(const std::vector<glm::vec3>& pts) {
    append<std::int32_t>(static_cast<std::int32_t>(pts.size()));
    for (const glm::vec3& p : pts) {
      append(p.x); append(p.y); append(p.z);
      for (int s = 0; s < ns_; ++s) append(7.0f + static_cast<float>(s));
    }
    for (int s = 0; s < np_; ++s) append(9.0f + static_cast<float>(s));
    ++count_;
  }
  std::vector<std::byte> bytes(bool write_count = true) {
    if (write_count) put<std::int32_t>(988, count_);
    return b_;
  }
  std::vector<std::byte> b_;
  bool big_;
  int ns_, np_, count_ = 0;
};

// Every segment's end points, in order.
std::vector<glm::vec3> segment_points(const Geometry& g) {
  std::vector<glm::vec3> v;
  for (const CapsulePrim& c : g.capsules) { v.push_back(c.a); v.push_back(c.b); }
  for (const RoundConePrim& c : g.round_cones) { v.push_back(c.a); v.push_back(c.b); }
  return v;
}

TEST(Trk, RealTracks300) {
  const std::string path = data_dir() + "/tracts/dipy_tracks300.trk";
  if (!std::filesystem::exists(path)) GTEST_SKIP() << "no tract data at " << path << " (set MASQ_DEFAULT_DATA_DIR)";
  WarnLog log;
  Scene s = load_trk(path, log.opts());
  const Geometry& g = s.geometries[0];
  EXPECT_EQ(g.type, PrimType::Capsule);
  EXPECT_EQ(g.capsules.size(), 14276u); // 14,576 points - 300 streamlines
  ASSERT_FALSE(g.capsules.empty());
  EXPECT_FLOAT_EQ(g.capsules[0].radius, kDefaultTrackRadius);
  ASSERT_EQ(log.lines.size(), 1u); // the default-radius warning
  EXPECT_NE(log.lines[0].find("radius"), std::string::npos);
  EXPECT_NO_THROW(validate_scene(s));

  WarnLog log2;
  Scene c = load_trk(path, log2.opts(PrimType::RoundCone, 0.25f));
  EXPECT_EQ(c.geometries[0].type, PrimType::RoundCone);
  EXPECT_EQ(c.geometries[0].round_cones.size(), 14276u);
  EXPECT_FLOAT_EQ(c.geometries[0].round_cones[0].ra, 0.25f);
  EXPECT_TRUE(log2.lines.empty());

  // The header, read independently of the loader: a little-endian version-2 header
  // with dim 50x50x50, voxel_size 1 1 1, vox_to_ras the identity, voxel_order "RAS"
  // (so the voxel axes agree with vox_to_ras and nothing is flipped), no scalars or
  // properties. world = identity * (voxmm / 1 - 0.5): every stored point moves by
  // -0.5 mm on each axis, from the voxel corner origin to the voxel centre one.
  std::vector<std::byte> bytes = read_file_bytes(path);
  auto f32 = [&](std::size_t o) { float v; std::memcpy(&v, bytes.data() + o, 4); return v; };
  auto i32 = [&](std::size_t o) { std::int32_t v; std::memcpy(&v, bytes.data() + o, 4); return v; };
  ASSERT_EQ(i32(996), 1000);
  EXPECT_EQ(i32(992), 2);
  for (int i = 0; i < 3; ++i) EXPECT_EQ(f32(12 + 4 * i), 1.0f);
  for (int row = 0; row < 4; ++row)
    for (int col = 0; col < 4; ++col) EXPECT_EQ(f32(440 + 4 * (4 * row + col)), row == col ? 1.0f : 0.0f);
  EXPECT_EQ(std::memcmp(bytes.data() + 948, "RAS", 4), 0);
  // The streamline and point counts and every segment, read independently of the loader.
  std::size_t off = 1000, n = 0, points = 0, k = 0;
  const std::vector<glm::vec3> loaded = segment_points(g);
  while (off + 4 <= bytes.size()) {
    const std::int32_t m = i32(off);
    for (std::int32_t i = 1; i < m; ++i, k += 2) {
      const std::size_t pa = off + 4 + 12 * static_cast<std::size_t>(i - 1), pb = pa + 12;
      ASSERT_LT(k + 1, loaded.size());
      EXPECT_EQ(loaded[k], glm::vec3(f32(pa) - 0.5f, f32(pa + 4) - 0.5f, f32(pa + 8) - 0.5f)) << "segment " << k / 2;
      EXPECT_EQ(loaded[k + 1], glm::vec3(f32(pb) - 0.5f, f32(pb + 4) - 0.5f, f32(pb + 8) - 0.5f)) << "segment " << k / 2;
    }
    off += 4 + 12 * static_cast<std::size_t>(m);
    points += static_cast<std::size_t>(m);
    ++n;
  }
  EXPECT_EQ(n, 300u);
  EXPECT_EQ(points, 14576u);
  EXPECT_EQ(points - n, g.capsules.size());
  EXPECT_EQ(k, loaded.size());
  // The first point, as stored (92.796928, 115.960747, 67.425522) less 0.5.
  EXPECT_FLOAT_EQ(g.capsules[0].a.x, 92.2969284f);
  EXPECT_FLOAT_EQ(g.capsules[0].a.y, 115.460747f);
  EXPECT_FLOAT_EQ(g.capsules[0].a.z, 66.9255219f);
}

TEST(Trk, ScalarsPropertiesAndUnknownCount) {
  TrkWriter w(2, 1);
  w.streamline({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}});
  w.streamline({{5, 5, 5}});
  w.streamline({{2, 2, 2}, {3, 3, 3}});
  for (bool with_count : {true, false}) {
    Scene s = load_trk(w.bytes(with_count), "mem.trk", LoadOptions{1.0f, PrimType::Capsule, {}});
    const Geometry& g = s.geometries[0];
    ASSERT_EQ(g.capsules.size(), 3u);
    EXPECT_EQ(g.capsules[1].b, glm::vec3(1, 1, 0));
    EXPECT_EQ(g.capsules[2].a, glm::vec3(2, 2, 2));
    EXPECT_EQ(g.capsules[2].b, glm::vec3(3, 3, 3));
  }
  expect_error([] { load_trk(TrkWriter().bytes(), "e.trk", LoadOptions{1.0f, PrimType::Sphere, {}}); },
               {"e.trk", "capsules or round cones"});
}

// The same tracts written little- and big-endian (header fields, counts, coordinates,
// scalars and properties all swapped) load point for point alike, with and without a
// vox_to_ras, with a known and an unknown n_count.
TEST(Trk, BigEndianEqualsLittleEndian) {
  const double v2r[3][4] = {{0, -4, 0, 10}, {2, 0, 0, -20}, {0, 0, 0.5, 5}};
  for (bool with_space : {false, true})
    for (bool with_count : {true, false}) {
      std::vector<std::byte> files[2];
      for (int big = 0; big < 2; ++big) {
        TrkWriter w(2, 3, big == 1);
        if (with_space) w.space(v2r, {2.0f, 4.0f, 0.5f}, "ALS", {10, 20, 30});
        w.streamline({{0, 0, 0}, {1, 0, 0}, {1, 1, 0.25f}});
        w.streamline({{5, 5, 5}});
        w.streamline({{2.5f, -2, 2}, {3, 3, 3}, {-1e3f, 7.125f, 1e-3f}, {4, 4, 4}});
        files[big] = w.bytes(with_count);
      }
      ASSERT_EQ(files[0].size(), files[1].size());
      ASSERT_NE(files[0], files[1]);
      EXPECT_EQ(files[1][996], std::byte{0x00}); // 1000 = 0x000003E8, most significant byte first
      EXPECT_EQ(files[1][999], std::byte{0xE8});
      WarnLog log_le, log_be;
      Scene le = load_trk(files[0], "le.trk", log_le.opts(PrimType::Capsule, 1.0f));
      Scene be = load_trk(files[1], "be.trk", log_be.opts(PrimType::Capsule, 1.0f));
      const std::vector<glm::vec3> a = segment_points(le.geometries[0]), b = segment_points(be.geometries[0]);
      ASSERT_EQ(a.size(), 2u * 5u);
      ASSERT_EQ(a.size(), b.size());
      for (std::size_t i = 0; i < a.size(); ++i) EXPECT_EQ(a[i], b[i]) << "point " << i;
      EXPECT_EQ(log_le.lines.size(), log_be.lines.size());
      if (!with_space) {
        EXPECT_EQ(a[0], glm::vec3(0, 0, 0)); // no vox_to_ras: voxmm as stored
      }
    }
}

// Points through a vox_to_ras, computed by hand: voxel = voxmm / voxel_size - 0.5, then
// world = vox_to_ras * voxel (after reorienting where voxel_order disagrees).
TEST(Trk, VoxToRasHandComputed) {
  auto load_points = [](TrkWriter& w, WarnLog& log) {
    w.streamline({{3, 10, 1.75f}, {1, 2, 0.25f}, {5, 6, 0.25f}});
    return segment_points(load_trk(w.bytes(), "v2r.trk", log.opts(PrimType::Capsule, 1.0f)).geometries[0]);
  };
  {
    // A 90 degree turn about z with voxel size 2 x 4 x 0.5 and a shift. Its columns run
    // along +y, -x, +z: axis codes "ALS", as the voxel_order says (lower case is fine).
    const double v2r[3][4] = {{0, -4, 0, 10}, {2, 0, 0, -20}, {0, 0, 0.5, 5}};
    for (const char* order : {"ALS", "als"}) {
      TrkWriter w;
      w.space(v2r, {2.0f, 4.0f, 0.5f}, order);
      WarnLog log;
      const std::vector<glm::vec3> p = load_points(w, log);
      ASSERT_EQ(p.size(), 4u);
      // (3, 10, 1.75) -> voxel (1, 2, 3) -> (-4*2 + 10, 2*1 - 20, 0.5*3 + 5)
      EXPECT_EQ(p[0], glm::vec3(2, -18, 6.5f));
      // (1, 2, 0.25) -> voxel (0, 0, 0) -> the translation
      EXPECT_EQ(p[1], glm::vec3(10, -20, 5));
      EXPECT_EQ(p[2], glm::vec3(10, -20, 5));
      // (5, 6, 0.25) -> voxel (2, 1, 0) -> (-4 + 10, 4 - 20, 5)
      EXPECT_EQ(p[3], glm::vec3(6, -16, 5));
      EXPECT_TRUE(log.lines.empty()) << (log.lines.empty() ? "" : log.lines[0]);
    }
  }
  // voxel_order disagreeing with vox_to_ras (an identity turn plus a shift, "RAS"):
  // the file's voxel axes are mapped onto vox_to_ras's first, as nibabel does.
  const double shift[3][4] = {{1, 0, 0, 1}, {0, 1, 0, 2}, {0, 0, 1, 3}};
  {
    // "LPS": x and y run the other way, so v -> dim - 1 - v on them. (3, 10, 1.75) ->
    // voxel (2.5, 9.5, 1.25) -> (10-1-2.5, 20-1-9.5, 1.25) -> + (1, 2, 3).
    for (const char* order : {"LPS", ""}) {
      TrkWriter w;
      w.space(shift, {1.0f, 1.0f, 1.0f}, order, {10, 20, 30});
      WarnLog log;
      const std::vector<glm::vec3> p = load_points(w, log);
      ASSERT_EQ(p.size(), 4u);
      EXPECT_EQ(p[0], glm::vec3(7.5f, 11.5f, 4.25f));
      EXPECT_EQ(p[1], glm::vec3(9.5f, 19.5f, 2.75f)); // (1, 2, 0.25) -> (0.5, 1.5, -0.25) -> (8.5, 17.5, -0.25)
      if (*order == '\0') { // empty: TrackVis's default LPS, said once
        ASSERT_EQ(log.lines.size(), 1u);
        EXPECT_NE(log.lines[0].find("offset 948"), std::string::npos) << log.lines[0];
        EXPECT_NE(log.lines[0].find("LPS"), std::string::npos) << log.lines[0];
      } else {
        EXPECT_TRUE(log.lines.empty());
      }
    }
  }
  {
    // "ARS": the file's x and y are vox_to_ras's y and x. (3, 10, 1.75) -> voxel
    // (2.5, 9.5, 1.25) -> (9.5, 2.5, 1.25) -> + (1, 2, 3).
    TrkWriter w;
    w.space(shift, {1.0f, 1.0f, 1.0f}, "ARS", {10, 20, 30});
    WarnLog log;
    const std::vector<glm::vec3> p = load_points(w, log);
    EXPECT_EQ(p[0], glm::vec3(10.5f, 4.5f, 4.25f));
  }
  // No vox_to_ras (version 2 with [3][3] = 0, or version 1 whatever the bytes there):
  // the points stay in voxmm, with one warning.
  for (int version : {2, 1}) {
    TrkWriter w;
    if (version == 1) {
      w.space(shift, {1.0f, 1.0f, 1.0f}, "LPS", {10, 20, 30}); // reserved bytes in version 1
      w.put<std::int32_t>(992, 1);
    }
    WarnLog log;
    const std::vector<glm::vec3> p = load_points(w, log);
    EXPECT_EQ(p[0], glm::vec3(3, 10, 1.75f));
    ASSERT_EQ(log.lines.size(), 1u);
    EXPECT_NE(log.lines[0].find("no vox_to_ras"), std::string::npos) << log.lines[0];
    EXPECT_NE(log.lines[0].find("voxel-mm"), std::string::npos) << log.lines[0];
  }
}

TEST(Trk, BadInputs) {
  TrkWriter w;
  w.streamline({{0, 0, 0}, {1, 0, 0}, {2, 0, 0}});
  const std::vector<std::byte> good = w.bytes();
  ASSERT_NO_THROW(load_trk(good, "good.trk"));
  auto load = [](std::vector<std::byte> b) { return [b] { load_trk(b, "bad.trk"); }; };

  // Truncated header / body.
  expect_error(load(std::vector<std::byte>(good.begin(), good.begin() + 500)), {"bad.trk", "offset 0", "header"});
  expect_error(load(std::vector<std::byte>(good.begin(), good.end() - 5)), {"bad.trk", "offset 1004", "truncated"});
  // Wrong magic.
  { auto b = good; b[0] = std::byte{'X'}; expect_error(load(b), {"bad.trk", "offset 0", "TRACK"}); }
  // Bad hdr_size, version.
  { TrkWriter x; x.put<std::int32_t>(996, 999); expect_error(load(x.bytes()), {"bad.trk", "offset 996", "hdr_size"}); }
  { TrkWriter x; x.put<std::int32_t>(992, 77); expect_error(load(x.bytes()), {"bad.trk", "offset 992", "version"}); }
  // n_count exceeding the file.
  { auto b = good; std::int32_t n = 5; std::memcpy(b.data() + 988, &n, 4);
    expect_error(load(b), {"bad.trk", "offset 1040", "1 of n_count 5"}); }
  { auto b = good; std::int32_t n = -1; std::memcpy(b.data() + 988, &n, 4);
    expect_error(load(b), {"bad.trk", "offset 988", "negative n_count"}); }
  // Point count exceeding the bytes left (huge: must fail before any allocation).
  { auto b = good; std::int32_t m = 0x7fffffff; std::memcpy(b.data() + 1000, &m, 4);
    expect_error(load(b), {"bad.trk", "offset 1004", "need"}); }
  { auto b = good; std::int32_t m = -3; std::memcpy(b.data() + 1000, &m, 4);
    expect_error(load(b), {"bad.trk", "offset 1000", "negative point count"}); }
  // NaN coordinate.
  { auto b = good; float nan = std::numeric_limits<float>::quiet_NaN(); std::memcpy(b.data() + 1004 + 12 + 4, &nan, 4);
    expect_error(load(b), {"bad.trk", "offset 1016", "point 1", "not finite"}); }
  // Negative n_scalars.
  { TrkWriter x; x.put<std::int16_t>(36, -2); expect_error(load(x.bytes()), {"bad.trk", "offset 36", "n_scalars"}); }
  // Big-endian files: the same checks, the same offsets.
  {
    TrkWriter x(0, 0, true);
    x.streamline({{0, 0, 0}, {1, 0, 0}, {2, 0, 0}});
    const std::vector<std::byte> be = x.bytes();
    ASSERT_NO_THROW(load_trk(be, "be.trk"));
    expect_error(load(std::vector<std::byte>(be.begin(), be.end() - 5)), {"bad.trk", "offset 1004", "truncated"});
    { auto b = be; b[1000] = std::byte{0x80}; expect_error(load(b), {"bad.trk", "offset 1000", "negative point count"}); }
    { auto b = be; b[988] = std::byte{0xFF}; expect_error(load(b), {"bad.trk", "offset 988", "negative n_count"}); }
    { TrkWriter y(0, 0, true); y.put<std::int32_t>(992, 77); expect_error(load(y.bytes()), {"bad.trk", "offset 992", "version"}); }
    { auto b = be; b[1004 + 12] = std::byte{0x7F}; b[1004 + 13] = std::byte{0xC0};  // x of point 1: NaN
      expect_error(load(b), {"bad.trk", "offset 1016", "point 1", "not finite"}); }
  }
  { TrkWriter x; x.put<std::int32_t>(996, 0x12345678); expect_error(load(x.bytes()), {"bad.trk", "offset 996", "expected 1000"}); }
  // A vox_to_ras that cannot be applied.
  const double ok[3][4] = {{2, 0, 0, 0}, {0, 2, 0, 0}, {0, 0, 2, 0}};
  auto spaced = [&](auto&& edit) {
    TrkWriter x;
    x.space(ok, {2.0f, 2.0f, 2.0f}, "RAS", {4, 4, 4});
    x.streamline({{0, 0, 0}, {1, 0, 0}});
    edit(x);
    return x.bytes();
  };
  ASSERT_NO_THROW(load_trk(spaced([](TrkWriter&) {}), "ok.trk"));
  { const double flat[3][4] = {{2, 0, 0, 0}, {0, 2, 0, 0}, {0, 0, 0, 0}}; // singular
    expect_error(load(spaced([&](TrkWriter& x) { x.space(flat, {2.0f, 2.0f, 2.0f}, "RAS"); })),
                 {"bad.trk", "offset 440", "singular"}); }
  { const double same[3][4] = {{2, 2, 0, 0}, {0, 0, 0, 0}, {0, 0, 2, 0}}; // two equal columns
    expect_error(load(spaced([&](TrkWriter& x) { x.space(same, {2.0f, 2.0f, 2.0f}, "RAS"); })),
                 {"bad.trk", "offset 440", "singular"}); }
  expect_error(load(spaced([](TrkWriter& x) { x.put<float>(440 + 4 * (4 * 1 + 2), std::numeric_limits<float>::infinity()); })),
               {"bad.trk", "offset 464", "vox_to_ras[1][2]", "not finite"});
  expect_error(load(spaced([](TrkWriter& x) { x.put<float>(16, 0.0f); })), {"bad.trk", "offset 16", "voxel_size[1]"});
  expect_error(load(spaced([](TrkWriter& x) { x.put<float>(20, -1.0f); })), {"bad.trk", "offset 20", "voxel_size[2]"});
  expect_error(load(spaced([](TrkWriter& x) { x.put<float>(12, std::numeric_limits<float>::quiet_NaN()); })),
               {"bad.trk", "offset 12", "voxel_size[0]"});
  for (const char* order : {"XYZ", "RRS", "RA", "RASX"})
    expect_error(load(spaced([&](TrkWriter& x) { x.space(ok, {2.0f, 2.0f, 2.0f}, order, {4, 4, 4}); })),
                 {"bad.trk", "offset 948", "voxel_order"});
  expect_error(load(spaced([&](TrkWriter& x) { x.space(ok, {2.0f, 2.0f, 2.0f}, "RPS", {4, 0, 4}); })),
               {"bad.trk", "offset 8", "dim[1]"});
  // A stored point that vox_to_ras carries past the float range.
  { const double huge[3][4] = {{1e30, 0, 0, 0}, {0, 1e30, 0, 0}, {0, 0, 1e30, 0}};
    TrkWriter x;
    x.space(huge, {1.0f, 1.0f, 1.0f}, "RAS");
    x.streamline({{0, 0, 0}, {1e10f, 0, 0}});
    expect_error(load(x.bytes()), {"bad.trk", "offset 1016", "point 1", "world"}); }
  expect_error([] { load_trk(std::string("/nonexistent/x.trk")); }, {"/nonexistent/x.trk", "cannot open"});
}

// ------------------------------------------------------------------------- MRtrix

template <class T>
void append_value(std::vector<std::byte>& b, T v, bool big) {
  unsigned char raw[sizeof(T)];
  std::memcpy(raw, &v, sizeof v);
  if (big)
    for (std::size_t i = 0; i < sizeof(T) / 2; ++i) std::swap(raw[i], raw[sizeof(T) - 1 - i]);
  for (unsigned char c : raw) b.push_back(static_cast<std::byte>(c));
}

// Writes a .tck the way MRtrix does: header, padding to the data offset, xyz triplets,
// a NaN triplet after each streamline, an Inf triplet at the end.
std::vector<std::byte> write_tck(const std::vector<std::vector<glm::vec3>>& tracks, const std::string& datatype = "Float32LE",
                                 bool terminate = true, std::size_t offset = 0) {
  std::string head = "mrtrix tracks\ntimestamp: 1.0\ndatatype: " + datatype + "\ncount: " + std::to_string(tracks.size()) + "\n";
  const std::size_t off = offset ? offset : head.size() + std::string("file: . 1000\nEND\n").size() + 3;
  head += "file: . " + std::to_string(off) + "\nEND\n";
  std::vector<std::byte> b = bytes_of(head);
  b.resize(off, std::byte{0});
  const bool big = datatype.ends_with("BE");
  const bool f64 = datatype.starts_with("Float64");
  auto put = [&](double x, double y, double z) {
    for (double v : {x, y, z}) {
      if (f64) append_value<double>(b, v, big);
      else append_value<float>(b, static_cast<float>(v), big);
    }
  };
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  for (const auto& t : tracks) {
    for (const glm::vec3& p : t) put(p.x, p.y, p.z);
    put(nan, nan, nan);
  }
  if (terminate) put(inf, inf, inf);
  return b;
}

const std::vector<std::vector<glm::vec3>> kTracks = {
    {{0, 0, 0}, {1, 0, 0}, {1, 2, 0}, {1, 2, 3}},
    {{-5.5f, 4.25f, 1e3f}, {-5.0f, 4.0f, 999.0f}},
    {{7, 7, 7}}, // one point: no segment
    {{0.1f, 0.2f, 0.3f}, {0.4f, 0.5f, 0.6f}, {0.7f, 0.8f, 0.9f}},
};

TEST(Tck, RoundTripAllDatatypes) {
  for (const char* dt : {"Float32LE", "Float32BE", "Float64LE", "Float64BE"}) {
    WarnLog log;
    Scene s = load_tck(write_tck(kTracks, dt), "rt.tck", log.opts(PrimType::RoundCone, 0.5f));
    const Geometry& g = s.geometries[0];
    ASSERT_EQ(g.type, PrimType::RoundCone) << dt;
    ASSERT_EQ(g.round_cones.size(), 3u + 1u + 0u + 2u) << dt;
    std::size_t k = 0;
    for (const auto& t : kTracks)
      for (std::size_t i = 1; i < t.size(); ++i, ++k) {
        EXPECT_EQ(g.round_cones[k].a, t[i - 1]) << dt << " segment " << k;
        EXPECT_EQ(g.round_cones[k].b, t[i]) << dt << " segment " << k;
        EXPECT_FLOAT_EQ(g.round_cones[k].ra, 0.5f);
        EXPECT_FLOAT_EQ(g.round_cones[k].rb, 0.5f);
      }
    EXPECT_TRUE(log.lines.empty()) << dt << ": " << (log.lines.empty() ? "" : log.lines[0]);
    EXPECT_NO_THROW(validate_scene(s));
  }
  // File path variant and capsules.
  const std::filesystem::path p = std::filesystem::temp_directory_path() / "masq_test_loaders_neuro.tck";
  {
    std::vector<std::byte> b = write_tck(kTracks);
    FILE* f = std::fopen(p.string().c_str(), "wb");
    ASSERT_NE(f, nullptr);
    ASSERT_EQ(std::fwrite(b.data(), 1, b.size(), f), b.size());
    std::fclose(f);
  }
  WarnLog log;
  Scene s = load_tck(p.string(), log.opts());
  std::filesystem::remove(p);
  EXPECT_EQ(s.geometries[0].capsules.size(), 6u);
  EXPECT_FLOAT_EQ(s.geometries[0].capsules[0].radius, kDefaultTrackRadius);
  EXPECT_EQ(log.lines.size(), 1u); // default radius
}

TEST(Tck, MissingTerminatorWarns) {
  WarnLog log;
  Scene s = load_tck(write_tck(kTracks, "Float32LE", false), "noend.tck", log.opts(PrimType::Capsule, 1.0f));
  EXPECT_EQ(s.geometries[0].capsules.size(), 6u);
  ASSERT_EQ(log.lines.size(), 1u);
  EXPECT_NE(log.lines[0].find("Inf terminator"), std::string::npos);
}

TEST(Tck, BadInputs) {
  const std::vector<std::byte> good = write_tck(kTracks);
  ASSERT_NO_THROW(load_tck(good, "good.tck"));
  auto load = [](std::vector<std::byte> b) { return [b] { load_tck(b, "bad.tck"); }; };
  auto text = [](const std::string& s) { return bytes_of(s); };

  // Wrong magic.
  { auto b = good; b[0] = std::byte{'X'}; expect_error(load(b), {"bad.tck", "offset 0", "mrtrix tracks"}); }
  // Header without END (truncated header).
  expect_error(load(text("mrtrix tracks\ndatatype: Float32LE\nfile: . 60\n")), {"bad.tck", "END"});
  // Unsupported datatype, malformed header line, bad file key.
  expect_error(load(text("mrtrix tracks\ndatatype: Int16LE\nfile: . 60\nEND\n")), {"bad.tck:2:", "datatype"});
  // A line without "key:" is skipped, as MRtrix does, so here the datatype is missing.
  expect_error(load(text("mrtrix tracks\ndatatype Float32LE\nfile: . 60\nEND\n")), {"bad.tck", "offset 0", "no datatype"});
  // The datatype that counts is the last; a bad one is named with its line.
  expect_error(load(text("mrtrix tracks\ndatatype: Float32LE\ndatatype: Int16LE\nfile: . 60\nEND\n")),
               {"bad.tck:3:", "datatype 'Int16LE'"});
  expect_error(load(text("mrtrix tracks\ndatatype: Float32LE\nfile: . 60\nfile: . x\nEND\n")), {"bad.tck:4:", "offset"});
  expect_error(load(text("mrtrix tracks\ndatatype: Float32LE\nfile: other.dat 0\nEND\n")), {"bad.tck:3:", "file: ."});
  expect_error(load(text("mrtrix tracks\ndatatype: Float32LE\nfile: . x\nEND\n")), {"bad.tck:3:", "offset"});
  expect_error(load(text("mrtrix tracks\nfile: . 40\nEND\n")), {"bad.tck", "datatype"});
  expect_error(load(text("mrtrix tracks\ndatatype: Float32LE\nEND\n")), {"bad.tck", "file: ."});
  // Data offset beyond the file / inside the header.
  expect_error(load(text("mrtrix tracks\ndatatype: Float32LE\nfile: . 99999\nEND\n")), {"bad.tck", "offset 99999", "beyond"});
  expect_error(load(text("mrtrix tracks\ndatatype: Float32LE\nfile: . 3\nEND\n")), {"bad.tck", "inside the header"});
  // Truncated mid-triplet.
  {
    auto b = write_tck(kTracks, "Float32LE", false);
    b.resize(b.size() - 5);
    expect_error(load(b), {"bad.tck", "offset", "truncated"});
  }
  // Partial NaN triplet.
  {
    auto b = write_tck({{{0, 0, 0}, {1, std::numeric_limits<float>::quiet_NaN(), 0}}});
    const std::size_t data_off = b.size() - 4 * 12; // 2 points, NaN triplet, Inf triplet
    expect_error(load(b), {"bad.tck", ("offset " + std::to_string(data_off + 12)).c_str(), "not finite"});
  }
  expect_error([] { load_tck(std::string("/nonexistent/x.tck")); }, {"/nonexistent/x.tck", "cannot open"});
}

// A header using what MRtrix's reader allows (docs "Tracks file format", File::KeyValue::
// Reader, Tractography::__ReaderBase__::open): comment lines and trailing comments,
// whitespace around keys and values, lines without a key (skipped, with a warning),
// repeated keys (datatype and file: the last counts; others are joined, so ignored
// here), keys and datatype names in any case, DOS line ends, "END" followed by a comment.
// "@" stands for the data offset, 512.
std::vector<std::byte> tck_with_header(const std::string& lines, const std::vector<std::vector<glm::vec3>>& tracks,
                                       bool dos = false) {
  std::vector<std::byte> b = write_tck(tracks, "Float32LE", true, 512);
  std::string h = "mrtrix tracks\n" + lines;
  for (std::size_t at; (at = h.find('@')) != std::string::npos;) h.replace(at, 1, "512");
  if (dos)
    for (std::size_t at = 0; (at = h.find('\n', at)) != std::string::npos; at += 2) h.replace(at, 1, "\r\n");
  EXPECT_LE(h.size(), 512u);
  std::fill(b.begin(), b.begin() + 512, std::byte{0});
  std::memcpy(b.data(), h.data(), h.size());
  return b;
}

TEST(Tck, HeaderAsMrtrixReadsIt) {
  const std::string lines =
      "# a comment line\n"                              // 2
      "   timestamp:   1.0   # a comment after a value\n" // 3
      "command_history: tckgen in.mif out.tck\n"          // 4
      "command_history: tckedit out.tck final.tck\n"      // 5: repeated, joined by MRtrix
      "this line has no colon\n"                          // 6: skipped
      ": a value without a key\n"                         // 7: skipped
      "DataType: Int16LE\n"                               // 8: overridden by line 9
      "datatype:   float32le\n"                           // 9
      "count: 4\n"                                        // 10
      "file: . 40\n"                                      // 11: overridden by line 12
      "  FILE : . @   # the data\n"                       // 12
      "END   # the header ends here\n";                   // 13
  for (bool dos : {false, true}) {
    WarnLog log;
    Scene s = load_tck(tck_with_header(lines, kTracks, dos), "h.tck", log.opts(PrimType::Capsule, 1.0f));
    const std::vector<glm::vec3> p = segment_points(s.geometries[0]);
    ASSERT_EQ(p.size(), 2u * 6u) << (dos ? "CRLF" : "LF");
    EXPECT_EQ(p[0], kTracks[0][0]);
    EXPECT_EQ(p.back(), kTracks[3][2]);
    ASSERT_EQ(log.lines.size(), 4u);
    EXPECT_NE(log.lines[0].find("h.tck:6:"), std::string::npos) << log.lines[0];
    EXPECT_NE(log.lines[0].find("ignored"), std::string::npos) << log.lines[0];
    EXPECT_NE(log.lines[1].find("h.tck:7:"), std::string::npos) << log.lines[1];
    EXPECT_NE(log.lines[2].find("h.tck:9:"), std::string::npos) << log.lines[2];
    EXPECT_NE(log.lines[2].find("earlier on line 8"), std::string::npos) << log.lines[2];
    EXPECT_NE(log.lines[3].find("h.tck:12:"), std::string::npos) << log.lines[3];
    EXPECT_NE(log.lines[3].find("earlier on line 11"), std::string::npos) << log.lines[3];
  }
  // The same key repeated with the same value: nothing to say.
  {
    WarnLog log;
    load_tck(tck_with_header("datatype: Float32LE\ndatatype: Float32LE\nfile: . @\nEND\n", kTracks), "same.tck",
             log.opts(PrimType::Capsule, 1.0f));
    EXPECT_TRUE(log.lines.empty()) << (log.lines.empty() ? "" : log.lines[0]);
  }
  // A repeated count is, as MRtrix joins it, no single number: not checked, said once;
  // so is a count that is not a number. A count that disagrees with the data is said.
  for (const char* count_lines : {"count: 4\ncount: 4\n", "count: many\n", "count: 3\n", "Count: 3\n"}) {
    WarnLog log;
    load_tck(tck_with_header(std::string("datatype: Float32LE\n") + count_lines + "file: . @\nEND\n", kTracks),
             "c.tck", log.opts(PrimType::Capsule, 1.0f));
    const std::string which = count_lines;
    if (which == "Count: 3\n") { // keys other than datatype and file are case-sensitive in MRtrix
      EXPECT_TRUE(log.lines.empty()) << (log.lines.empty() ? "" : log.lines[0]);
      continue;
    }
    ASSERT_EQ(log.lines.size(), 1u) << which;
    const char* expect = which == "count: 4\ncount: 4\n" ? "c.tck:4: 'count' given again (first on line 3)" : which == "count: many\n" ? "not a number" : "header count 3";
    EXPECT_NE(log.lines[0].find(expect), std::string::npos) << log.lines[0];
  }
}

// A .trk written from world points the way TrackVis files store them (voxmm =
// (inverse(vox_to_ras) * world + 0.5) * voxel_size) and a .tck of the same world points
// overlay, to fp32 rounding.
TEST(Trk, OverlaysTckOfTheSameTracts) {
  const std::vector<std::vector<glm::vec3>> tracks = {
      {{0, 0, 0}, {1, 0, 0}, {1, 2, 0}, {1, 2, 3}},
      {{-55.5f, 42.25f, 10.0f}, {-50.0f, 40.0f, 9.0f}},
      {{10.1f, -20.2f, 30.3f}, {40.4f, 50.5f, -60.6f}, {70.7f, 80.8f, 90.9f}},
  };
  const double c = std::cos(0.5), s = std::sin(0.5);
  struct Space { glm::dvec3 vs; const char* order; };
  // A turn of 0.5 rad about z with a shift: columns along R, A, S; then with the first
  // two voxel axes reversed: L, P, S.
  for (const Space sp : {Space{{2.0, 2.5, 3.0}, "RAS"}, Space{{-2.0, -2.5, 3.0}, "LPS"}}) {
    const glm::dvec3 t(-90.0, 126.0, -72.0);
    const glm::dmat3 rzs(glm::dvec3(c, s, 0) * sp.vs.x, glm::dvec3(-s, c, 0) * sp.vs.y, glm::dvec3(0, 0, 1) * sp.vs.z);
    const double v2r[3][4] = {{rzs[0][0], rzs[1][0], rzs[2][0], t.x},
                              {rzs[0][1], rzs[1][1], rzs[2][1], t.y},
                              {rzs[0][2], rzs[1][2], rzs[2][2], t.z}};
    const glm::dvec3 size = glm::abs(sp.vs);
    TrkWriter w;
    w.space(v2r, glm::vec3(size), sp.order);
    const glm::dmat3 inv = glm::inverse(rzs);
    for (const auto& tr : tracks) {
      std::vector<glm::vec3> voxmm;
      for (const glm::vec3& p : tr) voxmm.push_back(glm::vec3((inv * (glm::dvec3(p) - t) + 0.5) * size));
      w.streamline(voxmm);
    }
    WarnLog log;
    const std::vector<glm::vec3> a = segment_points(load_trk(w.bytes(), "o.trk", log.opts(PrimType::Capsule, 1.0f)).geometries[0]);
    const std::vector<glm::vec3> b = segment_points(load_tck(write_tck(tracks), "o.tck", log.opts(PrimType::Capsule, 1.0f)).geometries[0]);
    EXPECT_TRUE(log.lines.empty()) << (log.lines.empty() ? "" : log.lines[0]);
    ASSERT_EQ(a.size(), b.size());
    for (std::size_t i = 0; i < a.size(); ++i)
      for (int k = 0; k < 3; ++k) {
        // fp32 rounding of voxmm (at most ~300 here) carried through, and of the result
        const float tol = 8.0f * std::numeric_limits<float>::epsilon() * 300.0f;
        EXPECT_NEAR(a[i][k], b[i][k], tol) << sp.order << " point " << i << " axis " << k;
      }
  }
}

} // namespace
