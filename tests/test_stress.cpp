// The bounded subset of the numerical stress suite, exactly as `masq stress --quick
// --check` runs it: every primitive type on every backend, robust and fast, against the
// long-double oracle, with the CLI's rays per cell (SweepOptions' default, never fewer:
// a test that sampled less could pass where the command users run fails) and the CLI's
// acceptance (stress_failures). The fast mode must show the errors the robust forms
// remove (the suite has teeth). One test per primitive type (the curve's cells, the
// longest, in two parts), each running its cells of the whole list with the rays they
// have there (SweepOptions::only_types, shard_*), so ctest runs them side by side;
// together they are the whole `masq stress --quick`.
#include "stress/stress_report.h"
#include <gtest/gtest.h>
#include <cstdlib>
#include <iostream>
#include "tests/test_env.h"

using namespace masq;
using namespace masq::stress;

namespace {

struct Part {
  PrimType type;
  int index = 0, count = 1;
};
std::vector<Part> every_part() {
  std::vector<Part> parts;
  for (PrimType t : SweepOptions{}.types) {
    const int count = t == PrimType::Curve ? 2 : 1;
    for (int i = 0; i < count; ++i) parts.push_back({t, i, count});
  }
  return parts;
}

class Stress : public ::testing::TestWithParam<Part> {};

TEST_P(Stress, QuickSuiteOnEveryBackend) {
  StressOptions opt;
  opt.sweep.quick = true;
  opt.sweep.only_types = {GetParam().type};
  opt.sweep.shard_count = GetParam().count;
  opt.sweep.shard_index = GetParam().index;
  const StressReport r = run_stress(opt);
  std::cout << stress_matrix(r, Mode::Robust) << "\n"
            << stress_matrix(r, Mode::Fast) << "\n"
            << stress_by_kind(r) << "\n"
            << stress_summary(r);

  // Every backend ran (or the machine opted out of the missing ones).
  for (const auto& [b, why] : r.unavailable) {
    if (masq::test::missing_backends_allowed()) std::cout << "skipping " << b << ": " << why << "\n";
    else ADD_FAILURE() << b << " unavailable: " << why << " (set MASQ_ALLOW_MISSING_BACKENDS=1 to allow)";
  }
  ASSERT_FALSE(r.results.empty());

  // Robust mode: rate <= 1e-4, no false culls, no self hits, on every cell.
  std::string fails = stress_failures(r); // the CLI's --check, its default bound (1e-4)
  EXPECT_TRUE(fails.empty()) << fails;

  std::size_t fast_bad = 0, robust_bad = 0;
  for (const CellResult& c : r.results) {
    const std::string where = c.backend + " " + prim_type_key(c.spec.type) + " " + c.spec.label;
    // Well-conditioned hits are accurate: mean |dt|/r below 1e-3 within 1e4 radii and
    // lengths up to 1e4 radii (t carries u (D + L): 0.06 r at L = 1e6 r).
    if (c.mode == Mode::Robust && c.spec.distance_r <= 1e4 && c.spec.length_r <= 1e4 && c.spec.sweep != "invalid") {
      EXPECT_LT(c.m.mean_dt(), 1e-3) << where;
    }
    // NaN/Inf rays miss in both modes.
    if (c.spec.sweep == "invalid") {
      EXPECT_EQ(c.m.disagree, 0u) << where << " " << mode_name(c.mode);
    }
    // Quilez's capsule as written loses silhouette rays far away; the robust form must
    // not. If this fails, the suite can no longer tell the two apart.
    if (c.spec.type == PrimType::Capsule && c.backend == "cpu" && c.spec.sweep == "distance")
      (c.mode == Mode::Fast ? fast_bad : robust_bad) += c.m.disagree;
  }
  if (GetParam().type == PrimType::Capsule) {
    EXPECT_GT(fast_bad, 10 * robust_bad + 10);
  }
}

TEST(StressParts, TogetherTheyAreTheWholeQuickSuite) {
  SweepOptions whole;
  whole.quick = true;
  std::size_t cells = 0;
  for (const Part& p : every_part()) {
    SweepOptions o = whole;
    o.only_types = {p.type};
    o.shard_count = p.count;
    o.shard_index = p.index;
    for (const CellSpec& c : sweep_cells(o)) {
      const std::vector<CellSpec> all = sweep_cells(whole);
      const auto same = std::find_if(all.begin(), all.end(), [&](const CellSpec& w) {
        return w.ray_seed == c.ray_seed && w.label == c.label && w.type == c.type;
      });
      EXPECT_NE(same, all.end()) << c.label << ": not in the whole run, or with other rays";
      ++cells;
    }
  }
  EXPECT_EQ(cells, sweep_cells(whole).size());
  SweepOptions bad = whole;
  bad.shard_count = 2;
  bad.shard_index = 2;
  EXPECT_THROW(sweep_cells(bad), Error);
}

} // namespace

INSTANTIATE_TEST_SUITE_P(Types, Stress, ::testing::ValuesIn(every_part()), [](const ::testing::TestParamInfo<Part>& i) {
  std::string name = prim_type_key(i.param.type);
  if (i.param.count > 1) name += "_part" + std::to_string(i.param.index + 1) + "of" + std::to_string(i.param.count);
  return name;
});
