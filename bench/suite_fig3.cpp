// fig3: the masquerade paper's synthetic grid. Bundles of N parallel capsules (length 1,
// radius r, bundle radius 0.5) tilted by 0/15/30/45 degrees, seen orthographically
// along +z as in the paper; ref vs masq on every backend, primary rays.
#include "bench/driver_calls.h"
#include "bench/bench_report.h"
#include "bench/heatmap.h"
#include "bench/method_compare.h"
#include "bench/paper_tables.h"
#include "bench/rt_paper_fit.h"
#include "bench/suite.h"
#include "image/image_writer.h"
#include "scenes/generators.h"
#include <algorithm>
#include <chrono>
#include <fmt/format.h>
#include <optional>

namespace masq {

namespace {

struct Cell {
  int n;
  float r;
  double tilt;
};

// The cell of the call heat map: the paper's largest speedup (bench/paper_figures.h).
constexpr Cell kHeatmapCell = {1000, 0.002f, 15.0};

std::string paper_speedup(const Cell& c) {
  std::optional<double> p = paper_fig3_speedup(c.n, c.r, c.tilt);
  return p ? fmt::format("{:.2f}x", *p) : "-";
}

Scene fig3_scene(const Cell& c) { return fig3_bundle_scene(c.n, c.r, c.tilt); }

// quick: the paper's four (N, r) columns, so every cell has the paper's figure beside
// it; full: those and the 3 x 3 grid of N in {10, 100, 1000} x r in {0.01, 0.005, 0.002}.
std::vector<Cell> fig3_cells(bool quick) {
  std::vector<std::pair<int, float>> pairs;
  for (const PaperFig3Column& p : paper_fig3()) pairs.push_back({p.n, p.r});
  if (!quick)
    for (int n : {10, 100, 1000})
      for (float r : {0.01f, 0.005f, 0.002f})
        if (!paper_fig3_speedup(n, r, 0.0)) pairs.push_back({n, r});
  std::sort(pairs.begin(), pairs.end(), [](auto a, auto b) { return a.first != b.first ? a.first < b.first : a.second > b.second; });
  std::vector<Cell> cells;
  for (auto [n, r] : pairs)
    for (double tilt : kPaperFig3Tilts) cells.push_back({n, r, tilt});
  return cells;
}

std::string ratio_cell(const BenchRow* ref, const BenchRow* masq) {
  if (!ref || !masq) return "n/a";
  return fmt::format("{:.2f}x / {:.1f}x", masq->mrays_per_s() / ref->mrays_per_s(), ref->isect_calls / masq->isect_calls);
}

const BenchRow* counter_row(const std::vector<BenchRow>& rows, Method m) {
  for (const BenchRow& r : rows)
    if (r.method == m && r.unavailable.empty() && r.tlas_nodes >= 0) return &r;
  return nullptr;
}

} // namespace

Scene fig3_bundle_scene(int n, float r, double tilt) {
  BundleParams bp;
  bp.count = n;
  bp.radius = r;
  bp.tilt_deg = tilt;
  Scene s;
  s.name = fmt::format("bundle N={} r={} tilt {}", n, r, tilt);
  s.geometries.push_back(make_bundle(bp));
  s.instances.push_back({0, {}});
  s.camera.eye = {0.0, 0.0, -5.0};
  s.camera.target = {0.0, 0.0, 0.0};
  s.camera.orthographic = true;
  s.camera.ortho_height = 1.8;
  return s;
}

SuiteResult run_fig3(SuiteContext& ctx) {
  auto t0 = std::chrono::steady_clock::now();
  const bool quick = ctx.config.quick;
  const int side = quick ? 96 : 192;
  BenchOptions opt = ctx.bench_options(side, side);
  opt.ray_sets = {RaySet::Primary};
  opt.methods = {Method::Ref, Method::Masq, Method::Cluster, Method::Auto};
  std::vector<Cell> cells = fig3_cells(quick);
  std::vector<std::vector<BenchRow>> measured;
  SuiteResult res;
  res.name = "fig3";
  res.title = "Fig. 3: synthetic bundles, masq vs ref";
  for (std::size_t i = 0; i < cells.size(); ++i) {
    const Cell& c = cells[i];
    opt.progress = [&](const std::string& line) { ctx.say(fmt::format("fig3 {}/{} N={} r={} tilt {}: {}", i + 1, cells.size(), c.n, c.r, c.tilt, line)); };
    Scene scene = fig3_scene(c);
    measured.push_back(run_bench(scene, opt, ctx.pool));
  }
  // The RT model's prices, fitted to the paper's 16 cells from these rows' counters
  // (bench/rt_paper_fit.h); every later suite of this run prints predictions with them.
  std::vector<Fig3Rows> fit_cells;
  for (std::size_t i = 0; i < cells.size(); ++i) fit_cells.push_back({cells[i].n, cells[i].r, cells[i].tilt, &measured[i]});
  std::optional<RtFit> rt_fit = fit_rt_to_paper_fig3(fit_cells);
  if (rt_fit) ctx.rt_model = rt_fit->model;
  auto loo_of = [&](const Cell& c) -> const RtCellResult* {
    if (!rt_fit) return nullptr;
    std::string label = fmt::format("N={} r={:g} tilt {:g}", c.n, c.r, c.tilt);
    for (const RtCellResult& r : rt_fit->per_cell)
      if (r.label == label) return &r;
    return nullptr;
  };
  Table t;
  t.title = fmt::format("speedup masq/ref and intersector-call ratio ref/masq per backend ({}x{} orthographic primary rays)", side, side);
  t.header = {"N", "r", "tilt", "paper RTX 8000", "RT model", "RT model left out", "error left out", "calls ref/masq"};
  for (const std::string& b : opt.backends) t.header.push_back(b);
  t.left_columns = 0;  // numbers, aligned right
  t.label_columns = 3; // N, r, tilt name a cell
  res.data["cells"] = nlohmann::json::array();
  std::vector<Fig3Measured> grid;
  for (std::size_t i = 0; i < cells.size(); ++i) {
    const Cell& c = cells[i];
    const std::vector<BenchRow>& rows = measured[i];
    const BenchRow* ref = counter_row(rows, Method::Ref);
    const BenchRow* masq = counter_row(rows, Method::Masq);
    std::vector<std::string> line = {std::to_string(c.n), fmt::format("{:g}", c.r), fmt::format("{:g}", c.tilt),
                                     paper_speedup(c),
                                     ref && masq ? fmt::format("{:.2f}x", rt_predicted_speedup(*ref, *masq, ctx.rt_model)) : "n/a",
                                     loo_of(c) ? fmt::format("{:.2f}x", loo_of(c)->loo) : "-",
                                     loo_of(c) ? fmt::format("{:+.1f}%", 100 * loo_of(c)->loo_error()) : "-",
                                     ref && masq ? fmt::format("{:.1f}x", ref->isect_calls / masq->isect_calls) : "n/a"};
    for (const std::string& b : opt.backends)
      line.push_back(ratio_cell(find_row(rows, b, Method::Ref, RaySet::Primary), find_row(rows, b, Method::Masq, RaySet::Primary)));
    t.add(line);
    Fig3Measured g{c.n, c.r, c.tilt, ref && masq ? rt_predicted_speedup(*ref, *masq, ctx.rt_model) : 0.0, {}};
    for (const std::string& b : opt.backends) {
      const BenchRow* br = find_row(rows, b, Method::Ref, RaySet::Primary);
      const BenchRow* bm = find_row(rows, b, Method::Masq, RaySet::Primary);
      if (br && bm) g.speedup[b] = bm->mrays_per_s() / br->mrays_per_s();
    }
    grid.push_back(g);
    std::optional<double> paper = paper_fig3_speedup(c.n, c.r, c.tilt);
    nlohmann::json cell = {{"n", c.n}, {"r", c.r}, {"tilt_deg", c.tilt},
                           {"paper_rtx_speedup", paper ? nlohmann::json(*paper) : nlohmann::json()},
                           {"rt_model_speedup", g.rt_model}};
    if (const RtCellResult* l = loo_of(c)) cell["rt_model_left_out"] = {{"speedup", l->loo}, {"rel_error", l->loo_error()}};
    for (const BenchRow& r : rows) cell["results"].push_back(bench_row_json(r));
    res.data["cells"].push_back(cell);
  }
  t.notes = {"each backend: speedup / intersector-call ratio (rayquery and rtpipeline count the driver's calls)",
             "paper RTX 8000: the masquerade paper's Fig. 3, measured with OptiX 7 on an RTX 8000; '-': a cell outside "
             "its grid",
             rt_model_note(ctx.rt_model),
             fmt::format("RT model left out: the cell predicted by prices fitted to the other {} cells (leave-one-out); "
                         "error: against the paper's figure", rt_fit ? rt_fit->cells - 1 : 0)};
  res.tables.push_back(t);
  res.tables.push_back(fig3_paper_grid(grid, opt.backends));
  // The issue-7 methods on the same rays: oriented clusters, and the automatic choice.
  Table mt;
  mt.title = "cluster and auto on the same rays";
  mt.header = {"N", "r", "tilt"};
  for (const std::string& b : opt.backends) mt.header.push_back(b);
  mt.left_columns = 0;
  mt.label_columns = 3;
  MethodTally tally;
  for (std::size_t i = 0; i < cells.size(); ++i) {
    std::vector<std::string> line = {std::to_string(cells[i].n), fmt::format("{:g}", cells[i].r),
                                     fmt::format("{:g}", cells[i].tilt)};
    for (const std::string& b : opt.backends) line.push_back(method_cell(measured[i], b, RaySet::Primary, tally));
    mt.add(line);
  }
  nlohmann::json fit;
  mt.notes = {method_note(tally), price_fit_note(measured, opt.backends, fit)};
  res.data["price_fit"] = fit;
  res.tables.push_back(mt);
  std::vector<DriverCallsCase> driver_cases;
  for (std::size_t i = 0; i < cells.size(); ++i)
    driver_cases.push_back({{std::to_string(cells[i].n), fmt::format("{:g}", cells[i].r), fmt::format("{:g}", cells[i].tilt)},
                            &measured[i]});
  Table dt = driver_calls_table("the driver's traversal: intersector calls per ray and rays/s", {"N", "r", "tilt"},
                                driver_cases, opt.backends, RaySet::Primary, res.data["driver_calls"]);
  if (!dt.rows.empty()) res.tables.push_back(dt);
  res.data["auto_target"] = {{"cells", tally.cells}, {"within_5_percent", tally.auto_within}, {"worst", tally.worst},
                             {"kept_within_5_percent", tally.kept_within}, {"kept_worst", tally.kept_worst}};
  res.data["rt_model"] = rt_fit_json(rt_fit);
  res.method = fmt::format(
      "Bundles of N parallel capsules (length 1, radius r, bundle radius 0.5) tilted in the x-y plane, {}x{} "
      "orthographic rays along +z, {} mode; per cell and backend the same rays through ref (one AABB BLAS), masq (one "
      "instance per capsule), cluster (one instance per oriented cluster) and auto (docs/methods.md); median of {} timed traces after {} warm-up.",
      side, side, mode_name(ctx.config.mode), opt.repetitions, opt.warmup);
  res.images.push_back({"fig3_speedup.png", "Speedup masq/ref per cell and backend beside the paper's (RTX 8000) and "
                                            "the RT model's prediction (scripts/plot_results.py)"});
  if (!ctx.config.out_dir.empty() && !image_output_built()) {
    ctx.say("fig3 heatmap skipped: this masq was built without image output (-DMASQ_WITH_IMAGES=OFF)");
  } else if (!ctx.config.out_dir.empty()) {
    Scene scene = fig3_scene(kHeatmapCell);
    res.images.push_back(write_call_heatmaps(ctx, scene, "heatmap_bundle.png",
                                             "Intersector calls per pixel, ref (left) vs masq (right), bundle N=1000 r=0.002 tilt 15"));
  }
  res.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return res;
}

} // namespace masq
