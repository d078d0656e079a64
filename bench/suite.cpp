#include "bench/suite.h"
#include "bench/error_mode.h"
#include "masq/error.h"
#include "scenes/generators.h"
#include <algorithm>
#include <chrono>
#include <fmt/format.h>

namespace masq {

BenchOptions SuiteContext::bench_options(int width, int height) const {
  BenchOptions o;
  o.backends = config.backends;
  o.width = width;
  o.height = height;
  o.warmup = 1;
  o.repetitions = config.quick ? 3 : 5;
  o.accel.mode = config.mode;
  o.accel.nodes = config.nodes;
  o.node_formats = {config.nodes};
  o.auto_by = config.auto_by;
  return o;
}

const std::vector<std::string>& suite_names() {
  static const std::vector<std::string> names = suite_table.names();
  return names;
}

SuiteResult run_error_suite(SuiteContext& ctx) {
  auto t0 = std::chrono::steady_clock::now();
  const bool quick = ctx.config.quick;
  BundleParams bp;
  bp.prim = PrimType::Curve;
  bp.count = quick ? 100 : 300;
  Scene scene = make_default_scene(bp);
  BenchOptions opt = ctx.bench_options(quick ? 64 : 160, quick ? 48 : 120);
  opt.progress = [&](const std::string& line) { ctx.say("error: " + line); };
  std::vector<ErrorRow> rows = run_error_bench(scene, default_error_variants(), opt, ctx.pool);
  SuiteResult res;
  res.name = "error";
  res.title = "Run time against error (curve intersector variants)";
  res.tables.push_back(error_table(rows));
  res.data = error_json(rows);
  res.method = fmt::format(
      "{} cubic curves (r=0.002, tilt 45) over a ground plane, {}x{} primary rays, masq method; every variant's hits "
      "compared with the long-double oracle of the exact cubics (rays with clearance < 1e-3 r counted as ambiguous). "
      "Plot: error_vs_time.png.",
      bp.count, opt.width, opt.height);
  res.images.push_back({"error_vs_time.png", "Run time against error per backend (Pareto front marked *)"});
  res.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return res;
}

std::vector<SuiteResult> run_suites(SuiteContext& ctx, const std::vector<std::string>& names) {
  for (const std::string& n : names) suite_table.at(n); // throws masq::Error naming the suites
  auto wants = [&](const char* n) { return std::find(names.begin(), names.end(), n) != names.end(); };
  auto timed = [](auto&& f) {
    auto t0 = std::chrono::steady_clock::now();
    SuiteResult r = f();
    r.seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return r;
  };
  std::vector<SuiteResult> out;
  if (wants("fig3")) out.push_back(run_fig3(ctx));
  const bool hair_views = wants("table1") || wants("table2") || wants("fig9") || wants("fig10");
  if (hair_views) {
    auto t0 = std::chrono::steady_clock::now();
    collect_hair_measurements(ctx, wants("table1"));
    double collect = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (wants("table1")) out.push_back(table1_result(ctx));
    if (wants("table2")) out.push_back(table2_result(ctx));
    if (wants("fig9")) out.push_back(fig9_result(ctx));
    if (wants("fig10")) out.push_back(timed([&] { return fig10_result(ctx); }));
    // The shared measurement is charged to the first hair view that ran.
    for (SuiteResult& r : out)
      if (r.name == "table1" || r.name == "table2" || r.name == "fig9" || r.name == "fig10") {
        r.seconds += collect;
        break;
      }
  }
  if (wants("error")) out.push_back(run_error_suite(ctx));
  if (wants("peers")) out.push_back(run_peers(ctx));
  if (wants("bv")) out.push_back(run_bv_suite(ctx));
  return out;
}

} // namespace masq
