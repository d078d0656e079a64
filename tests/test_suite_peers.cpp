// The peers suite (bench/suite_peers.cpp) run for real: its quick form on the cpu
// backend against Embree 3.
#include "bench/suite.h"
#include <gtest/gtest.h>
#include <set>
#include <string>

using namespace masq;

// A real quick peers run on the cpu backend: masq's tracer of each ray set is chosen on
// pilot rays (a camera of another resolution: never the timed rays) by CPU time, over
// both builders' structures, and timed round by round against both of Embree's APIs by CPU and wall
// time, each ratio with its spread, a short ray set traced several times per sample; the
// builds timed alone, round by round; or the Embree columns say why not.
TEST(Suites, PeersQuickOnCpuChoosesOnPilotRaysAndTimesRoundByRound) {
  SuiteContext ctx;
  ctx.config.quick = true;
  ctx.config.backends = {"cpu"};
  ctx.config.data_dir = MASQ_DATA_DIR;
  std::vector<SuiteResult> runs = run_suites(ctx, {"peers"});
  ASSERT_EQ(runs.size(), 1u);
  const SuiteResult& out = runs[0];
  const nlohmann::json& scenes = out.data["scenes"];
  ASSERT_EQ(scenes.size(), 3u); // the bear as capsules and as curves, and the default bundle
  EXPECT_TRUE(out.data["indicative"].get<bool>());
  int sets = 0;
  for (const auto& sc : scenes) {
    std::set<std::string> builders;
    for (const auto& r : sc["pilot"]["rows"]) builders.insert(r["builder"].get<std::string>());
    EXPECT_EQ(builders, (std::set<std::string>{"sah", "sah4"})) << sc["scene"];
    const int pilot_rays = sc["pilot"]["width"].get<int>() * sc["pilot"]["height"].get<int>();
    const int timed_rays = sc["timed"]["width"].get<int>() * sc["timed"]["height"].get<int>();
    EXPECT_NE(sc["pilot"]["width"], sc["timed"]["width"]); // other pixel centres: other rays
    EXPECT_GE(sc["timed"]["rounds"].get<int>(), 5);
    for (const auto& p : sc["peers"]) {
      ++sets;
      EXPECT_EQ(p["masq_choice"]["backend"], "cpu");
      EXPECT_TRUE(builders.count(p["masq_choice"]["builder"].get<std::string>()));
      // The choice is the pilot row of the set with the least CPU time per trace.
      double least = 0;
      for (const auto& r : sc["pilot"]["rows"]) {
        if (r["rays"] != p["rays"] || r.contains("unavailable")) continue;
        const double c = r["cpu_seconds"].get<double>();
        EXPECT_GT(c, 0.0) << r.dump();
        if (least == 0 || c < least) least = c;
      }
      EXPECT_EQ(p["masq_choice"]["cpu_seconds"].get<double>(), least) << p["rays"];
      if (p["rays"] == "primary") {
        EXPECT_EQ(p["ray_count"].get<int>(), timed_rays);
        EXPECT_LT(pilot_rays, timed_rays);
      }
      // A sample traces at least the camera's count of rays, a smaller set several times.
      const int passes = p["traces_per_sample"].get<int>();
      EXPECT_GE(passes * p["ray_count"].get<int>(), timed_rays) << p["rays"];
      EXPECT_LT((passes - 1) * p["ray_count"].get<int>(), timed_rays) << p["rays"];
      EXPECT_GT(p["masq"]["mrays_per_s"].get<double>(), 0.0);
      EXPECT_GT(p["masq"]["cpu_seconds"]["median"].get<double>(), 0.0);
      if (p["embree"].contains("unavailable")) continue;
      ASSERT_EQ(p["embree_apis"].size(), 2u) << p.dump();
      EXPECT_GT(p["embree"]["mrays_per_s"].get<double>(), 0.0);
      const auto& r = p["masq_over_embree_cpu"];
      EXPECT_GT(r["median"].get<double>(), 0.0);
      EXPECT_LE(r["min"].get<double>(), r["median"].get<double>());
      EXPECT_LE(r["median"].get<double>(), r["max"].get<double>());
      EXPECT_GT(p["masq_over_embree_wall"]["median"].get<double>(), 0.0);
    }
  }
  EXPECT_EQ(sets, 9); // primary, shadow and diffuse of each scene
  // The build table: masq's two structures and Embree's scene built alone, round by
  // round, a time per round each.
  for (const auto& sc : scenes) {
    const nlohmann::json& b = sc["builds"];
    for (const char* who : {"ref", "masq", "embree"}) {
      if (std::string(who) == "embree" && !b.contains("embree")) continue; // masq built without Embree
      const auto& w = b[who]["wall_seconds"];
      EXPECT_GT(w["min"].get<double>(), 0.0) << sc["scene"] << " " << who;
      EXPECT_LE(w["min"].get<double>(), w["median"].get<double>()) << who;
      EXPECT_LE(w["median"].get<double>(), w["max"].get<double>()) << who;
      EXPECT_GT(b[who]["cpu_seconds"]["median"].get<double>(), 0.0) << who;
    }
  }
  ASSERT_GE(out.tables.size(), 2u);
  EXPECT_NE(out.tables[1].title.find("round by round"), std::string::npos);
  for (const auto& row : out.tables[1].rows)
    for (const auto& cell : row) EXPECT_EQ(cell.find("unavailable"), std::string::npos) << cell;
  for (const auto& row : out.tables.front().rows)
    for (const auto& cell : row) EXPECT_EQ(cell.find("unavailable"), std::string::npos) << cell;
}
