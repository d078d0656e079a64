// masq bench: one scene through every backend x method with the same rays.
#include "bench/bench_report.h"
#include "bench/price_fit.h"
#include "bench/rt_paper_fit.h"
#include "bench/error_mode.h"
#include "bench/results_doc.h"
#include "bench/suite.h"
#include "cli/commands.h"
#include "cli/device_option.h"
#include "cli/scene_options.h"
#include "masq/error.h"
#include "masq/knobs.h"
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <algorithm>
#include <chrono>
#include <ctime>
#include <filesystem>
#include <functional>
#include <cstdlib>
#include <fstream>
#include <map>
#include <memory>
#include <unistd.h>

namespace masq::cli {

namespace {
struct BenchCli {
  SceneOptions scene;
  std::vector<std::string> backends;
  std::string device; // --device (cli/device_option.h)
  std::vector<std::string> methods;
  bool fit_prices = false;
  BenchOptions bench;
  std::vector<std::string> ray_sets;
  std::string shadow_query = "any";
  std::string auto_by = "pilot";
  std::string json_path;
  bool quiet = false;
  bool error_mode = false;
  std::vector<std::string> suites;
  bool quick = false;
  std::string out_dir; // "": a new folder of this run's own (new_suite_folder)
  bool wide = false;   // the full tables after the headline
  std::string data_dir;
  std::string command_line;
  CLI::Option* count_opt = nullptr;
  CLI::Option* width_opt = nullptr;
  CLI::Option* height_opt = nullptr;
  CLI::Option* prim_opt = nullptr;
};

// --error: run time against error on a curve scene (bench/error_mode.h).
// One-line progress on stderr, only on a terminal (a log file gets no carriage returns).
std::function<void(const std::string&)> progress_line(bool quiet) {
  if (quiet || !isatty(2)) return {};
  auto t0 = std::chrono::steady_clock::now();
  return [t0](const std::string& line) {
    double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    fmt::print(stderr, "\r\033[K  [{:4.0f} s] {}", s, line.substr(0, 110));
  };
}

void clear_progress(bool quiet) {
  if (!quiet && isatty(2)) fmt::print(stderr, "\r\033[K");
}

std::string ray_sets_text(const std::vector<RaySet>& sets, bool shadow_any_hit) {
  std::string out;
  for (RaySet s : sets)
    out += std::string(out.empty() ? "" : ", ") + ray_set_name(s) +
           (s == RaySet::Shadow && shadow_any_hit ? " (occlusion: any hit)" : "");
  return out;
}

int bench_error(BenchCli& c) {
  // Smaller defaults than a speed run: every ray is also traced by the brute-force
  // long-double oracle.
  if (c.prim_opt->count() == 0) c.scene.prim = "curve";
  if (c.count_opt->count() == 0) c.scene.bundle.count = 300;
  if (c.width_opt->count() == 0) c.bench.width = 160;
  if (c.height_opt->count() == 0) c.bench.height = 120;
  if (c.scene.prim != "curve") throw Error("bench --error: needs --prim curve (the exact cubics are the reference)");
  Scene scene = make_scene(c.scene);
  c.bench.accel = accel_options(c.scene);
  if (!c.backends.empty()) c.bench.backends = c.backends;
  c.bench.progress = progress_line(c.quiet);
  fmt::print("run time against error: {} curves r={} tilt {} deg, {}x{} primary rays, masq method, {} warm-up + {} "
             "timed traces; error against the long-double oracle of the exact cubics (rays with clearance < 1e-3 "
             "counted as ambiguous)\n",
             c.scene.bundle.count, c.scene.bundle.radius, c.scene.bundle.tilt_deg, c.bench.width, c.bench.height,
             c.bench.warmup, c.bench.repetitions);
  BackendPool pool;
  std::vector<ErrorRow> rows = run_error_bench(scene, default_error_variants(), c.bench, pool);
  clear_progress(c.quiet);
  fmt::print("{}", error_table(rows).text());
  if (!c.json_path.empty()) {
    std::ofstream f(c.json_path);
    if (!f) throw Error("bench: cannot write '" + c.json_path + "'");
    f << error_json(rows).dump(2) << "\n";
    fmt::print("wrote {}\n", c.json_path);
  }
  return 0;
}

// What auto kept, and why: the model's cost per candidate (bvh/twolevel/structure_cost.h) and, by
// pilot, each candidate's pilot time on each backend and ray set.
void print_auto_choices(const std::vector<BenchRow>& rows, AutoBy by) {
  auto kept_name = [](const BenchRow& r) {
    std::string kept = r.build.auto_choice == Method::Auto ? "the mix" : method_name(r.build.auto_choice);
    if (r.build.auto_choice == Method::Cluster)
      kept += fmt::format(" (size {}, leaf price {:g})", r.build.cluster_size, r.build.cluster_leaf_price);
    return kept;
  };
  bool first = true;
  for (const BenchRow& r : rows) {
    if (r.method != Method::Auto || !r.unavailable.empty()) continue;
    const auto& k = r.build.auto_candidates;
    if (first)
      fmt::print("auto's candidates, model cost per ray: ref {:.3g}, masq {:.3g}, cluster {:.3g} (its cheapest shape), "
                 "mix {:.3g} (triangles' share {:.3g}; docs/methods.md)\n",
                 k[0], k[1], k[2], k[3], r.build.model_triangles);
    first = false;
    if (by == AutoBy::Model) {
      fmt::print("auto kept {} (by the model)\n", kept_name(r));
      return;
    }
    const auto& p = r.pilot_seconds;
    auto ms = [](double s) { return s > 0 ? fmt::format("{:.2f}", s * 1e3) : std::string("-"); };
    const std::string mix = r.pilot_mix_is_ref ? std::string("= ref (ref's structure)") : ms(p[3]);
    fmt::print("auto {} {}: kept {} by pilot ({} rays; ms ref {}, masq {}, cluster {}, mix {}; pilot {:.2f} s)\n",
               r.backend, ray_set_name(r.ray_set), kept_name(r), r.pilot_rays, ms(p[0]), ms(p[1]), ms(p[2]), mix,
               r.pilot_s);
  }
}

// The default output folder of a suite run: a new one in the working directory, named by
// the run's start (masq-suites-YYYYmmdd-HHMMSS[-quick], then -2, -3 if taken), so a run
// never writes over another's, nor over the repository's reference results
// (bench/results*, which scripts/results.sh writes with --out on purpose).
std::string new_suite_folder(bool quick) {
  const std::time_t now = std::time(nullptr);
  std::tm utc{};
  gmtime_r(&now, &utc);
  char stamp[32];
  std::strftime(stamp, sizeof stamp, "%Y%m%d-%H%M%S", &utc);
  const std::string base = std::string("masq-suites-") + stamp + (quick ? "-quick" : "");
  std::string name = base;
  for (int k = 2; std::filesystem::exists(name); ++k) name = base + "-" + std::to_string(k);
  return name;
}

// --suite: the papers' tables and figures, the results document and its raw figures.
int bench_suites(BenchCli& c) {
  std::vector<std::string> names = c.suites;
  if (std::find(names.begin(), names.end(), "all") != names.end()) names = suite_names();
  SuiteContext ctx;
  ctx.config.quick = c.quick;
  if (c.out_dir.empty()) {
    c.out_dir = new_suite_folder(c.quick);
    fmt::print(stderr, "masq bench: writing the suites' results to {}/ (--out chooses the folder)\n", c.out_dir);
  }
  ctx.config.out_dir = c.out_dir;
  ctx.config.mode = parse_mode(c.scene.mode);
  ctx.config.auto_by = parse_auto_by(c.auto_by);
  if (!c.backends.empty()) ctx.config.backends = c.backends;
  if (std::vector<NodeFormat> f = node_formats(c.scene); f.size() == 1) ctx.config.nodes = f[0];
  ctx.config.data_dir = !c.data_dir.empty() ? c.data_dir : knob_text(Knob::Data).value_or(MASQ_DATA_DIR);
  ctx.config.progress = progress_line(c.quiet);
  auto t0 = std::chrono::steady_clock::now();
  nlohmann::json machine = machine_description(ctx.pool, ctx.config.backends);
  std::vector<SuiteResult> results = run_suites(ctx, names);
  clear_progress(c.quiet);
  for (const SuiteResult& r : results) {
    fmt::print("== {} ({}, {:.0f} s)\n", r.title, r.name, r.seconds);
    for (const Table& t : r.tables) fmt::print("{}\n", t.text());
  }
  ResultsRun run{c.command_line, c.quick, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count()};
  write_results(c.out_dir, results, machine, run);
  fmt::print("wrote {0}/RESULTS.md and {0}/results.json in {1:.0f} s (plots: /usr/bin/python3 scripts/plot_results.py {0})\n",
             c.out_dir, run.seconds);
  return 0;
}

int bench(BenchCli& c) {
  if (!c.suites.empty()) return bench_suites(c);
  if (c.error_mode) return bench_error(c);
  Scene scene = make_scene(c.scene);
  c.bench.accel = accel_options(c.scene);
  if (!c.backends.empty()) c.bench.backends = c.backends;
  if (!c.methods.empty()) {
    c.bench.methods.clear();
    for (const std::string& m : c.methods) c.bench.methods.push_back(parse_method(m));
  }
  if (!c.ray_sets.empty()) {
    c.bench.ray_sets.clear();
    for (const std::string& r : c.ray_sets) c.bench.ray_sets.push_back(parse_ray_set(r));
  }
  c.bench.shadow_any_hit = query_table.parse(c.shadow_query) == Query::Any;
  c.bench.auto_by = parse_auto_by(c.auto_by);
  c.bench.builders = parse_builders(c.scene);
  c.bench.node_formats = node_formats(c.scene);
  c.bench.curve_isects = curve_isects(c.scene);
  c.bench.progress = progress_line(c.quiet);
  const bool bundle = c.scene.file.empty() && embedded_scene_table.parse(c.scene.scene) == EmbeddedScene::Bundle;
  // Short lines (the headline is read in 100 columns): the scene, the structure, the rays, the timing.
  fmt::print("scene '{}': {} primitives{}\n", scene.name, scene.primitive_count(),
             bundle ? fmt::format(" ({} {} strands r={} tilt {} deg + ground plane)", c.scene.bundle.count, c.scene.prim,
                                  c.scene.bundle.radius, c.scene.bundle.tilt_deg)
                    : std::string());
  fmt::print("  {} mode, nodes {}, {} masquerade entries, builders {}, auto by {}\n", c.scene.mode,
             fmt::join(c.scene.nodes, ","), c.scene.masq_instance, fmt::join(c.scene.builders, ", "),
             auto_by_name(c.bench.auto_by));
  fmt::print("  {}x{} camera rays; ray sets: {}\n", c.bench.width, c.bench.height,
             ray_sets_text(c.bench.ray_sets, c.bench.shadow_any_hit));
  // auto's pilot times each candidate no more often than the rows are timed: --reps 3
  // asks for a quicker run, and the pilot is a fifth of the default bench's traces.
  c.bench.pilot.rounds = std::min(c.bench.pilot.rounds, c.bench.repetitions);
  fmt::print("  {} warm-up + {} timed traces each, median of device time\n", c.bench.warmup, c.bench.repetitions);
  std::vector<BenchRow> rows = run_bench(scene, c.bench);
  clear_progress(c.quiet);
  const Table headline = bench_headline(rows);
  if (!headline.rows.empty()) fmt::print("\n{}", headline.text());
  if (c.wide) {
    // The RT model's prices: fitted to the paper's Fig. 3 from the cpu backend's counters
    // on its 16 bundles (bench/rt_paper_fit.h), measured now; without a cpu backend the
    // model says it is unfitted.
    RtCostModel rt_model;
    try {
      BackendPool pool;
      if (std::optional<RtFit> fit = measure_and_fit_rt_fig3(pool)) rt_model = fit->model;
    } catch (const std::exception& e) {
      rt_model.source = std::string("not fitted: ") + e.what();
    }
    Table ratios = bench_ratios(rows, rt_model);
    Table builders = bench_builders(rows);
    fmt::print("\n{}\n{}", bench_table(rows).text(),
               ratios.rows.empty() ? std::string("(no ratios: ref and another method must run on a backend)\n")
                                   : ratios.text());
    if (c.bench.node_formats.size() > 1) fmt::print("\nnode formats side by side:\n{}", bench_node_ratios(rows).text());
    if (c.bench.curve_isects.size() > 1)
      fmt::print("\ncurve intersectors side by side:\n{}", bench_curve_isect_ratios(rows).text());
    print_auto_choices(rows, c.bench.auto_by);
    if (!builders.rows.empty()) fmt::print("\nbuilders side by side:\n{}", builders.text());
  } else {
    // Methods without ref (the headline's baseline) still get their own lines.
    if (headline.rows.empty()) fmt::print("{}", bench_table(rows).text());
    fmt::print("every figure per row (counters, memory, build and compile times, auto's choices): --wide\n"
               "all of them as JSON: --json FILE\n");
  }
  if (c.fit_prices) {
    // The auto method's cost-model prices for each backend, fitted to these rows.
    for (const std::string& b : c.bench.backends) {
      std::optional<PriceFit> f = fit_prices(rows, b);
      if (!f) {
        fmt::print("prices {}: not enough rows with counters to fit (run ref, masq and cluster)\n", b);
        continue;
      }
      fmt::print("prices {}: --prices 1 {:.3g} {:.3g}  (node {:.3g} ns per visit, {:.3g} ns per ray, {} rows, fit error "
                 "median {:.0f}%, worst {:.0f}%)\n",
                 b, f->prices.transform, f->prices.isect, f->ns_per_node, f->ns_per_ray, f->rows,
                 100.0 * f->median_rel_error, 100.0 * f->max_rel_error);
    }
  }
  if (!c.json_path.empty()) {
    std::ofstream f(c.json_path);
    if (!f) throw Error("bench: cannot write '" + c.json_path + "'");
    f << bench_json(scene, c.bench, rows).dump(2) << "\n";
    fmt::print("wrote {}\n", c.json_path);
  }
  for (const BenchRow& r : rows)
    if (!r.unavailable.empty()) return 1;
  return 0;
}
} // namespace

Action add_bench(CLI::App& app) {
  auto c = std::make_shared<BenchCli>();
  CLI::App* cmd = app.add_subcommand("bench", "Trace the scene on every backend x method: rays/s, counters, memory");
  add_scene_options(*cmd, c->scene);
  c->count_opt = cmd->get_option("--count");
  c->prim_opt = cmd->get_option("--prim");
  cmd->add_flag("--error", c->error_mode,
                "Run time against error: every curve intersector variant vs the long-double oracle (Pareto table)");
  cmd->add_option("--backend", c->backends, "Backends to run (default: all): " + backend_table.help())
      ->delimiter(',')
      ->check(CLI::IsMember(backend_table.names()));
  add_device_option(*cmd, c->device);
  cmd->add_option("--method", c->methods, "Methods to run (default: all): " + method_table.help())
      ->delimiter(',')
      ->check(CLI::IsMember(method_table.names()));
  c->width_opt = cmd->add_option("--width", c->bench.width, "Rays per row")->capture_default_str()->check(CLI::Range(1, 16384));
  c->height_opt = cmd->add_option("--height", c->bench.height, "Rows of rays")->capture_default_str()->check(CLI::Range(1, 16384));
  cmd->add_option("--warmup", c->bench.warmup, "Untimed traces first")->capture_default_str()->check(CLI::NonNegativeNumber);
  cmd->add_option("--reps", c->bench.repetitions, "Timed traces (and at most as many pilot traces of each of auto's candidates)")->capture_default_str()->check(CLI::PositiveNumber);
  cmd->add_option("--rays", c->ray_sets, "Ray sets (default: all): " + ray_set_table.help())
      ->check(CLI::IsMember(ray_set_table.names()));
  cmd->add_option("--shadow-query", c->shadow_query, "What shadow rays ask for: " + query_table.help())
      ->capture_default_str()
      ->check(CLI::IsMember(query_table.names()));
  cmd->add_option("--auto-by", c->auto_by,
                  "How auto keeps one of its candidates (ref, masq, cluster, the mix): " + auto_by_table.help())
      ->capture_default_str()
      ->check(CLI::IsMember(auto_by_table.names()));
  cmd->add_flag("--fit-prices", c->fit_prices,
                "Fit the auto method's cost-model prices per backend to the measured rows (docs/methods.md)");
  cmd->add_option("--json", c->json_path, "Also write every raw figure as JSON");
  cmd->add_flag("--wide", c->wide,
                "Print every figure per row (rates, counters, memory, build and compile times, the method ratios and "
                "auto's choices; about 200 columns) after the headline");
  std::vector<std::string> suites = suite_names();
  suites.push_back("all");
  cmd->add_option("--suite", c->suites,
                  "Reproduce the papers' tables: " + suite_table.help() +
                      "; or all; writes OUT/RESULTS.md and OUT/results.json")
      ->check(CLI::IsMember(suites));
  cmd->add_flag("--quick", c->quick, "Suites: the small variant (fewer cases, fewer rays; docs/results.md gives its run time)");
  cmd->add_option("--out", c->out_dir, "Suites: output directory of RESULTS.md, results.json and images (default: "
                                        "a new folder masq-suites-<UTC date-time>[-quick] in the working directory)");
  cmd->add_option("--data", c->data_dir, "Suites: directory of the shared scenes (default: $MASQ_DATA or " MASQ_DATA_DIR ")");
  cmd->add_flag("-q,--quiet", c->quiet, "No progress display");
  cmd->footer("Examples:\n"
              "  masq bench                                   default bundle, every backend x method x ray set\n"
              "  masq bench --file bear.tfx --prim curve --subdiv 4 --backend cpu --rays primary\n"
              "  masq bench --nodes w4,w8,q8 --method ref,masq   node formats side by side (speed, visits, bytes)\n"
              "  masq bench --error --json error.json         run time against error of the curve variants\n"
              "  masq bench --builder sah,sbvh,sah+reinsert,sbvh+reinsert --method ref,masq --backend cpu,opencl\n"
              "                                               the BVH builders side by side (SAH cost, refs/prim, speed)\n"
              "  masq bench --suite all --quick               the papers' tables, small variant -> masq-suites-<date>-quick/\n"
              "  masq bench --device vulkan=1,opencl=nvidia   choose the devices (indices and names: masq info)\n"
              "  bash scripts/results.sh                      the full results document with plots");
  return [c] {
    c->command_line = "masq bench";
    for (const std::string& s : c->suites) c->command_line += " --suite " + s;
    if (c->quick) c->command_line += " --quick";
    apply_device_option(c->device, c->backends.empty() ? backend_names() : c->backends);
    return bench(*c);
  };
}

} // namespace masq::cli
