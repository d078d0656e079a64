// The TrackVis .trk loader: the real .trk from MASQ_DATA_DIR, files built from the
// format's byte layout (either byte order, vox_to_ras), a .trk and a .tck of the same
// tracts overlaying, and one handmade broken input per error class. The MRtrix .tck
// loader's own tests: test_loaders_tck.cpp.
#include "scenes/loaders/load_tracks.h"
#include "tests/loader_test_util.h"
#include "tests/tck_writer.h"
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
