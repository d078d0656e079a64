// auto chosen by pilot (bench/auto_pilot.h): the sample, the choice rule against a backend
// whose times are set by the test, the choice on a real backend where one candidate is
// several times faster, and the bench's auto rows (bench/bench_runner.h).
#include "bench/auto_pilot.h"
#include "bench/bench_report.h"
#include "bench/bench_runner.h"
#include "bench/suite.h"
#include "scenes/camera.h"
#include "masq/error.h"
#include "scenes/generators.h"
#include <gtest/gtest.h>
#include <map>

using namespace masq;

namespace {

std::vector<kernel::Ray> numbered_rays(std::size_t n) {
  std::vector<kernel::Ray> rays(n);
  for (std::size_t i = 0; i < n; ++i) rays[i].org[0] = float(i); // the ray's index, to find it again
  return rays;
}

// A backend whose trace time is what the test says for the uploaded structure's
// candidate (PackedScene::method); it records what it was asked.
class TimedFake : public Backend {
 public:
  std::map<Method, double> seconds;
  std::vector<Method> uploads;
  std::vector<Query> queries;
  std::string name() const override { return "fake"; }
  std::string device_name() const override { return "fake"; }
  void set_scene(const PackedScene& s) override {
    current_ = s.method;
    uploads.push_back(s.method);
  }
  void trace(std::span<const kernel::Ray>, std::span<kernel::Hit>, std::span<kernel::RayStats>, Query q) override {
    queries.push_back(q);
    timing_.trace_seconds = seconds.at(current_);
  }
  TraceTiming timing() const override { return timing_; }
  std::size_t device_bytes() const override { return 0; }

 private:
  Method current_ = Method::Ref;
  TraceTiming timing_;
};

AutoCandidates fake_candidates() {
  AutoCandidates c;
  for (Method m : {Method::Ref, Method::Masq, Method::Cluster, Method::Auto}) {
    PackedScene p;
    p.method = m;
    c.built.push_back(p);
  }
  return c;
}

} // namespace

TEST(PilotSample, AllRaysWhenFew) {
  std::vector<kernel::Ray> rays = numbered_rays(1000);
  std::vector<kernel::Ray> s = pilot_sample(rays, 1000);
  ASSERT_EQ(s.size(), 1000u);
  for (std::size_t i = 0; i < s.size(); ++i) EXPECT_EQ(s[i].org[0], float(i));
}

TEST(PilotSample, RunsOfConsecutiveRaysSpanningTheSet) {
  std::vector<kernel::Ray> rays = numbered_rays(100000);
  std::vector<kernel::Ray> s = pilot_sample(rays, 4096);
  ASSERT_EQ(s.size(), 4096u);
  EXPECT_EQ(s.front().org[0], 0.0f);
  EXPECT_EQ(s.back().org[0], 99999.0f); // the last run ends at the last ray
  std::size_t breaks = 0;
  for (std::size_t i = 1; i < s.size(); ++i) {
    EXPECT_GT(s[i].org[0], s[i - 1].org[0]) << "in order, no ray twice";
    breaks += s[i].org[0] != s[i - 1].org[0] + 1.0f;
  }
  EXPECT_EQ(breaks, 4096u / 256u - 1u) << "runs of 256 consecutive rays";
}

TEST(AutoPilot, KeepsTheFastestAndTimesEveryCandidate) {
  TimedFake be;
  be.seconds = {{Method::Ref, 0.010}, {Method::Masq, 0.004}, {Method::Cluster, 0.002}, {Method::Auto, 0.003}};
  AutoCandidates c = fake_candidates();
  std::vector<kernel::Ray> rays = numbered_rays(100000);
  PilotOptions opt;
  opt.rounds = 2;
  opt.max_rays = 4096;
  PilotResult r = run_pilot(be, c, rays, Query::Any, opt);
  EXPECT_EQ(c.built[r.kept].method, Method::Cluster);
  ASSERT_EQ(r.seconds.size(), 4u);
  EXPECT_DOUBLE_EQ(r.seconds[0], 0.010);
  EXPECT_DOUBLE_EQ(r.seconds[2], 0.002);
  EXPECT_EQ(r.rays, opt.max_rays);
  EXPECT_EQ(be.uploads.size(), 4u) << "each candidate uploaded once";
  EXPECT_EQ(be.queries.size(), 4u * 3u) << "one warm-up and `rounds` timed traces each";
  EXPECT_EQ(be.uploads, (std::vector<Method>{Method::Ref, Method::Masq, Method::Cluster, Method::Auto}));
  for (Query q : be.queries) EXPECT_EQ(q, Query::Any) << "the caller's query";
}

TEST(AutoPilot, OneSlotPerCandidateTakesTurns) {
  std::vector<TimedFake> fakes(4);
  const double secs[] = {0.010, 0.004, 0.002, 0.003};
  const Method ms[] = {Method::Ref, Method::Masq, Method::Cluster, Method::Auto};
  std::vector<Backend*> slots;
  for (std::size_t i = 0; i < fakes.size(); ++i) {
    fakes[i].seconds[ms[i]] = secs[i]; // at() throws if a slot traces another candidate
    slots.push_back(&fakes[i]);
  }
  AutoCandidates c = fake_candidates();
  std::vector<kernel::Ray> rays = numbered_rays(500);
  PilotResult r = run_pilot(slots, c, rays, Query::Closest);
  EXPECT_EQ(c.built[r.kept].method, Method::Cluster);
  for (const TimedFake& f : fakes) {
    EXPECT_EQ(f.uploads.size(), 1u);
    EXPECT_EQ(f.queries.size(), std::size_t(PilotOptions{}.rounds + 1));
  }
  // Slots that hold the candidates already are not uploaded to again.
  PilotOptions again;
  again.slots_hold_candidates = true;
  run_pilot(slots, c, rays, Query::Closest, again);
  for (const TimedFake& f : fakes) EXPECT_EQ(f.uploads.size(), 1u);
  // Two slots for four candidates: neither one nor one each.
  std::vector<Backend*> two = {slots[0], slots[1]};
  EXPECT_THROW(run_pilot(two, c, rays, Query::Closest), Error);
}

TEST(AutoPilot, RefStaysWithinTheMargin) {
  TimedFake be;
  AutoCandidates c = fake_candidates();
  std::vector<kernel::Ray> rays = numbered_rays(100);
  // masq 1% faster than ref: within the 2% margin, ref (the smallest) stays.
  be.seconds = {{Method::Ref, 0.0100}, {Method::Masq, 0.0099}, {Method::Cluster, 0.02}, {Method::Auto, 0.02}};
  EXPECT_EQ(c.built[run_pilot(be, c, rays, Query::Closest).kept].method, Method::Ref);
  // 10% faster: masq.
  be.seconds[Method::Masq] = 0.009;
  EXPECT_EQ(c.built[run_pilot(be, c, rays, Query::Closest).kept].method, Method::Masq);
  // With no margin, 1% is enough.
  be.seconds[Method::Masq] = 0.0099;
  PilotOptions none;
  none.ref_margin = 0;
  EXPECT_EQ(c.built[run_pilot(be, c, rays, Query::Closest, none).kept].method, Method::Masq);
}

TEST(AutoPilot, BadArgumentsAreNamed) {
  TimedFake be;
  std::vector<kernel::Ray> rays = numbered_rays(10);
  EXPECT_THROW(run_pilot(be, AutoCandidates{}, rays, Query::Closest), Error);
  PilotOptions bad;
  bad.rounds = 0;
  try {
    run_pilot(be, fake_candidates(), rays, Query::Closest, bad);
    FAIL() << "rounds 0 accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("rounds"), std::string::npos) << e.what();
  }
  bad = {};
  bad.ref_margin = 1.5;
  EXPECT_THROW(run_pilot(be, fake_candidates(), rays, Query::Closest, bad), Error);
  EXPECT_THROW(parse_auto_by("fastest"), Error);
  EXPECT_EQ(parse_auto_by("model"), AutoBy::Model);
}

// The paper's worst case for AABBs: 1000 strands at 45 degrees, where ref makes several
// times the intersector calls of the others. On the real cpu backend the pilot must see
// it; at tilt 0 no candidate has anything to gain over ref by that much.
TEST(AutoPilot, RealBackendLeavesRefWhereItIsSlow) {
  std::unique_ptr<Backend> be = make_backend("cpu");
  Scene s = fig3_bundle_scene(1000, 0.002f, 45.0);
  AutoCandidates c = build_auto_candidates(s, {});
  ASSERT_EQ(c.built.size(), 4u);
  std::vector<kernel::Ray> rays = make_camera_rays(s.camera, 96, 96);
  PilotResult r = run_pilot(*be, c, rays, Query::Closest);
  EXPECT_NE(c.built[r.kept].method, Method::Ref);
  EXPECT_LT(r.seconds[r.kept], r.seconds[0]);
  // The kept structure marked as auto's: the same hits as ref's.
  PackedScene kept = c.built[r.kept];
  mark_as_auto(kept, c);
  EXPECT_EQ(kept.method, Method::Auto);
  EXPECT_EQ(kept.stats.auto_choice, c.built[r.kept].method);
  std::vector<kernel::Hit> a(rays.size()), b(rays.size());
  be->set_scene(kept);
  be->trace(rays, a, {});
  be->set_scene(c.built[0]);
  be->trace(rays, b, {});
  int hits = 0;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    ASSERT_EQ(a[i].prim, b[i].prim) << "ray " << i;
    hits += a[i].prim >= 0;
  }
  EXPECT_GT(hits, 100);
}

// The bench's auto rows by pilot: each backend and ray set runs its own pilot, the row
// describes the structure kept (bytes, build figures) and carries every candidate's time;
// the methods' rows are measured in the same rounds from their own backend slots.
TEST(AutoPilot, BenchRowsCarryThePilot) {
  BundleParams bp;
  bp.count = 300;
  bp.tilt_deg = 45;
  Scene scene = make_default_scene(bp);
  BenchOptions opt;
  opt.backends = {"cpu"};
  opt.methods = {Method::Ref, Method::Masq, Method::Cluster, Method::Auto};
  opt.ray_sets = {RaySet::Primary, RaySet::Shadow};
  opt.width = 64;
  opt.height = 48;
  opt.warmup = 0;
  opt.repetitions = 2;
  opt.keep_per_ray = true;
  std::vector<BenchRow> rows = run_bench(scene, opt);
  ASSERT_EQ(rows.size(), 8u);
  AutoCandidates c = build_auto_candidates(scene, opt.accel);
  for (const BenchRow& r : rows) {
    ASSERT_TRUE(r.unavailable.empty()) << r.unavailable;
    EXPECT_GT(r.median_s, 0.0);
    if (r.method != Method::Auto) {
      EXPECT_EQ(r.pilot_rays, 0u);
      continue;
    }
    EXPECT_EQ(r.pilot_rays, std::size_t(r.rays)) << "fewer rays than the pilot's sample: all of them";
    for (const PackedScene& cand : c.built) EXPECT_GT(r.pilot_seconds[std::size_t(cand.method)], 0.0);
    // The row's structure is the kept candidate's.
    const PackedScene* kept = nullptr;
    for (const PackedScene& cand : c.built)
      if (cand.method == r.build.auto_choice) kept = &cand;
    ASSERT_NE(kept, nullptr);
    EXPECT_EQ(r.accel_bytes, kept->acceleration_bytes());
    EXPECT_EQ(r.build.instances, kept->stats.instances);
    // Its hits are ref's on the same rays (shadow rays: any hit, so occluded or not).
    const BenchRow* ref = find_row(rows, "cpu", Method::Ref, r.ray_set);
    ASSERT_NE(ref, nullptr);
    ASSERT_EQ(r.hits.size(), ref->hits.size());
    for (std::size_t i = 0; i < r.hits.size(); ++i)
      if (r.query == Query::Closest)
        ASSERT_EQ(r.hits[i].prim, ref->hits[i].prim) << "ray " << i;
      else
        ASSERT_EQ(r.hits[i].prim >= 0, ref->hits[i].prim >= 0) << "ray " << i;
    nlohmann::json j = bench_row_json(r);
    EXPECT_EQ(j["auto"]["pilot"]["rays"], r.pilot_rays);
  }
  // By the model: no pilot.
  opt.auto_by = AutoBy::Model;
  opt.methods = {Method::Auto};
  for (const BenchRow& r : run_bench(scene, opt)) EXPECT_EQ(r.pilot_rays, 0u);
}
