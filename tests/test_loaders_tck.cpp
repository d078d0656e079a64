// The MRtrix .tck loader: files written the way MRtrix writes them (every datatype, either
// byte order), a round trip, a missing terminator, the header rules MRtrix's reader
// allows, and one handmade broken input per error class.
#include "scenes/loaders/load_tracks.h"
#include "tests/loader_test_util.h"
#include "tests/tck_writer.h"
#include <gtest/gtest.h>
#include <algorithm>
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

} // namespace
