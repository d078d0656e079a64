// The SWC loader: real neurons from MASQ_DATA_DIR and one handmade broken input per
// error class (TrackVis and MRtrix: test_loaders_tracks.cpp).
#include "scenes/loaders/load_swc.h"
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
// ------------------------------------------------------------------------- SWC

TEST(Swc, RealNeurons) {
  const std::string dir = data_dir() + "/neurons";
  if (!std::filesystem::is_directory(dir)) GTEST_SKIP() << "no neuron data at " << dir << " (set MASQ_DEFAULT_DATA_DIR)";
  const char* files[] = {"C031097B-I4.CNG.swc", "C040600B3.CNG.swc", "C080400A3.CNG.swc", "C220498B-I4.CNG.swc"};
  std::size_t warned_files = 0;
  for (const char* f : files) {
    const std::string path = dir + "/" + f;
    if (!std::filesystem::exists(path)) GTEST_SKIP() << "missing " << path;
    WarnLog log;
    Scene s = load_swc(path, log.opts());
    ASSERT_EQ(s.geometries.size(), 1u);
    ASSERT_EQ(s.instances.size(), 1u);
    const Geometry& g = s.geometries[0];
    EXPECT_EQ(g.type, PrimType::RoundCone) << f;
    // Each file has one root (the soma), so segments = samples - 1, samples in [4911, 5543].
    EXPECT_GE(g.round_cones.size() + 1, 4911u) << f;
    EXPECT_LE(g.round_cones.size() + 1, 5543u) << f;
    for (const RoundConePrim& c : g.round_cones) {
      ASSERT_GE(c.ra, 0.0f) << f;
      ASSERT_GE(c.rb, 0.0f) << f;
    }
    EXPECT_NO_THROW(validate_scene(s)) << f;
    if (!log.lines.empty()) {
      ++warned_files;
      EXPECT_NE(log.lines[0].find("negative radius"), std::string::npos) << log.lines[0];
    }
  }
  // Exact counts (samples - roots), as counted independently from the files.
  {
    Scene a = load_swc(dir + "/C040600B3.CNG.swc");
    EXPECT_EQ(a.geometries[0].round_cones.size(), 5542u);
    Scene b = load_swc(dir + "/C220498B-I4.CNG.swc");
    EXPECT_EQ(b.geometries[0].round_cones.size(), 4910u);
    Scene c = load_swc(dir + "/C080400A3.CNG.swc");
    EXPECT_EQ(c.geometries[0].round_cones.size(), 5242u);
    WarnLog log;
    Scene d = load_swc(dir + "/C031097B-I4.CNG.swc", log.opts());
    EXPECT_EQ(d.geometries[0].round_cones.size(), 5419u);
    ASSERT_EQ(log.lines.size(), 1u);
    EXPECT_NE(log.lines[0].find("negative radius"), std::string::npos);
  }
  EXPECT_EQ(warned_files, 1u) << "exactly one real file has negative radii";
}

TEST(Swc, GapsRootsForwardParentsComments) {
  const std::string text =
      "# comment\n"
      "\n"
      "10 1 0 0 0 2.0 -1   # soma\r\n"
      "12 3 1 0 0 0.5 10\n"
      "30 3 3 0 0 0.25 20\n"  // parent listed later
      "20 3 2 0 0 0.5 12\n"
      "100 1 9 9 9 1.0 -1\n"  // second root
      "101 3 9 9 10 0.3 100 extra columns ignored\n"
      "200 1 5 5 5 1.0 -1\n"; // isolated root: nothing
  Scene s = load_swc(bytes_of(text), "mem.swc");
  const Geometry& g = s.geometries[0];
  ASSERT_EQ(g.type, PrimType::RoundCone);
  ASSERT_EQ(g.round_cones.size(), 4u);
  // 12 -> 10
  EXPECT_EQ(g.round_cones[0].a, glm::vec3(0, 0, 0));
  EXPECT_FLOAT_EQ(g.round_cones[0].ra, 2.0f);
  EXPECT_EQ(g.round_cones[0].b, glm::vec3(1, 0, 0));
  EXPECT_FLOAT_EQ(g.round_cones[0].rb, 0.5f);
  // 30 -> 20 (forward reference)
  EXPECT_EQ(g.round_cones[1].a, glm::vec3(2, 0, 0));
  EXPECT_FLOAT_EQ(g.round_cones[1].rb, 0.25f);
  // Radius scale.
  LoadOptions o;
  o.radius = 2.0f;
  Scene t = load_swc(bytes_of(text), "mem.swc", o);
  EXPECT_FLOAT_EQ(t.geometries[0].round_cones[0].ra, 4.0f);
}

TEST(Swc, NegativeRadiusRepairedWithWarning) {
  WarnLog log;
  Scene s = load_swc(bytes_of("1 1 0 0 0 1 -1\n2 3 1 0 0 -0.275 1\n"), "neg.swc", log.opts());
  ASSERT_EQ(s.geometries[0].round_cones.size(), 1u);
  EXPECT_FLOAT_EQ(s.geometries[0].round_cones[0].rb, 0.275f);
  ASSERT_EQ(log.lines.size(), 1u);
  EXPECT_NE(log.lines[0].find("neg.swc"), std::string::npos);
  EXPECT_NE(log.lines[0].find("line 2"), std::string::npos);
}

TEST(Swc, BadInputs) {
  auto load = [](const std::string& text) { return [text] { load_swc(bytes_of(text), "bad.swc"); }; };
  expect_error(load("1 1 0 0 0 1 -1\n2 3 1 0 0 0.5\n"), {"bad.swc:2:", "7 fields"});          // malformed: too few
  expect_error(load("1 1 0 0 0 1 -1\n2 3 1 zero 0 0.5 1\n"), {"bad.swc:2:", "not a number"}); // non-numeric
  expect_error(load("1 1 0 0 0 1 -1\nx 3 1 0 0 0.5 1\n"), {"bad.swc:2:", "id"});               // non-numeric id
  expect_error(load("1 1 0 0 0 1 -1\n2 3 1 nan 0 0.5 1\n"), {"bad.swc:2:", "not finite"});     // NaN
  expect_error(load("1 1 0 0 0 1 -1\n2 3 1 0 0 inf 1\n"), {"bad.swc:2:", "not finite"});       // Inf
  expect_error(load("1 1 0 0 0 1 -1\n2 3 1 0 0 1e400 1\n"), {"bad.swc:2:", "not finite"});     // overflow
  expect_error(load("1 1 0 0 0 1 -1\n2 3 1 0 0 0.5 1\n3 3 2 0 0 0.5 7\n"), {"bad.swc:3:", "parent 7"}); // bad parent
  expect_error(load("1 1 0 0 0 1 -1\n2 3 1 0 0 0.5 1\n2 3 2 0 0 0.5 1\n"), {"bad.swc:3:", "duplicate id 2", "line 2"});
  expect_error(load("1 1 0 0 0 1 -1\n2 3 1 0 0 0.5 2\n"), {"bad.swc:2:", "own parent"});
  // Parent links in a loop (no root): named with the samples and lines of the loop,
  // whether the file also has a proper tree or not, and however long the loop is.
  expect_error(load("1 1 0 0 0 1 -1\n2 3 1 0 0 0.5 1\n5 3 2 0 0 0.5 7\n6 3 3 0 0 0.5 5\n7 3 4 0 0 0.5 6\n"),
               {"bad.swc:", "loop with no root", "sample 5 -> 7 -> 6 -> 5", "lines 3, 5, 4"});
  expect_error(load("1 3 0 0 0 1 2\n2 3 1 0 0 0.5 1\n"), {"bad.swc:", "loop with no root", "1 -> 2 -> 1"});
  {
    std::string ring;
    for (int i = 1; i <= 20; ++i) ring += std::to_string(i) + " 3 " + std::to_string(i) + " 0 0 0.5 " +
                                          std::to_string(i == 20 ? 1 : i + 1) + "\n";
    expect_error(load(ring), {"bad.swc:1:", "loop with no root", "(20 samples)", "lines 1, 2, 3"});
  }
  expect_error(load("# nothing\n"), {"bad.swc", "no segments"});
  expect_error(load("1 1 0 0 0 1 -1\n"), {"bad.swc", "no segments"});
  expect_error(load(std::string("1 1 0 0 0 1 -1\n2 3 1 0 0 0.5 1\n\0\1\2", 33)), {"bad.swc:3:"}); // binary junk
  expect_error([] { load_swc(std::string("/nonexistent/x.swc")); }, {"/nonexistent/x.swc", "cannot open"});
}

} // namespace
