// masq bench: one scene through every backend x method with the same rays.
#include "bench/bench_report.h"
#include "bench/error_mode.h"
#include "cli/commands.h"
#include "cli/scene_options.h"
#include "scenes/error.h"
#include <fmt/format.h>
#include <fstream>
#include <memory>

namespace masq::cli {

namespace {
struct BenchCli {
  SceneOptions scene;
  std::vector<std::string> backends;
  std::vector<std::string> methods;
  BenchOptions bench;
  std::string json_path;
  bool quiet = false;
  bool error_mode = false;
  CLI::Option* count_opt = nullptr;
  CLI::Option* width_opt = nullptr;
  CLI::Option* height_opt = nullptr;
  CLI::Option* prim_opt = nullptr;
};

// --error: run time against error on a curve scene (bench/error_mode.h).
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
  if (!c.quiet) c.bench.progress = [](const std::string& line) { fmt::print(stderr, "\r\033[K  {}", line); };
  fmt::print("run time against error: {} curves r={} tilt {} deg, {}x{} primary rays, masq method, {} warm-up + {} "
             "timed traces; error against the long-double oracle of the exact cubics (rays with clearance < 1e-3 "
             "counted as ambiguous)\n",
             c.scene.bundle.count, c.scene.bundle.radius, c.scene.bundle.tilt_deg, c.bench.width, c.bench.height,
             c.bench.warmup, c.bench.repetitions);
  std::vector<ErrorRow> rows = run_error_bench(scene, default_error_variants(), c.bench);
  if (!c.quiet) fmt::print(stderr, "\r\033[K");
  fmt::print("{}", error_table(rows));
  fmt::print("cubic <mode> it<N> x<k>: phantom curves, N iterations, each cubic pre-split into k; linear xN: each "
             "curve as N capsules.\npareto *: no other variant on that backend is at once faster, fewer disagreements "
             "and smaller mean |dt|/r\n");
  if (!c.json_path.empty()) {
    std::ofstream f(c.json_path);
    if (!f) throw Error("bench: cannot write '" + c.json_path + "'");
    f << error_json(rows).dump(2) << "\n";
    fmt::print("wrote {}\n", c.json_path);
  }
  return 0;
}

int bench(BenchCli& c) {
  if (c.error_mode) return bench_error(c);
  Scene scene = make_scene(c.scene);
  c.bench.accel = accel_options(c.scene);
  if (!c.backends.empty()) c.bench.backends = c.backends;
  if (!c.methods.empty()) {
    c.bench.methods.clear();
    for (const std::string& m : c.methods) c.bench.methods.push_back(parse_method(m));
  }
  if (!c.quiet) c.bench.progress = [](const std::string& line) { fmt::print(stderr, "\r\033[K  {}", line); };
  const bool bundle = c.scene.file.empty() && c.scene.scene == "bundle";
  fmt::print("scene '{}': {} primitives{}, {} mode, {}x{} primary rays, {} warm-up + {} timed traces, median (min-max) "
             "of device time\n",
             scene.name, scene.primitive_count(),
             bundle ? fmt::format(" ({} {} strands r={} tilt {} deg + ground plane)", c.scene.bundle.count, c.scene.prim,
                                  c.scene.bundle.radius, c.scene.bundle.tilt_deg)
                    : std::string(),
             c.scene.mode, c.bench.width, c.bench.height, c.bench.warmup, c.bench.repetitions);
  std::vector<BenchRow> rows = run_bench(scene, c.bench);
  if (!c.quiet) fmt::print(stderr, "\r\033[K");
  fmt::print("{}\n{}", bench_table(rows), bench_ratios(rows));
  fmt::print("per ray: tlas/blas = wide-node visits, xf = instance transforms, isect = intersector calls "
             "(rayquery: the driver's traversal is not observable, n/a);\n"
             "accel MiB / B/prim: masq's own two-level BVH (nodes, refs, instances, frames); dev MiB: what the backend holds "
             "on the device (rayquery: the driver's acceleration structures plus primitives); build ms: host build + upload/driver build\n");
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
  cmd->add_option("--backend", c->backends, "Backends to run (default: all)")->check(CLI::IsMember({"cpu", "vulkan", "opencl", "rayquery"}));
  cmd->add_option("--method", c->methods, "Methods to run (default: ref masq)")->check(CLI::IsMember({"ref", "masq"}));
  c->width_opt = cmd->add_option("--width", c->bench.width, "Rays per row")->capture_default_str()->check(CLI::Range(1, 16384));
  c->height_opt = cmd->add_option("--height", c->bench.height, "Rows of rays")->capture_default_str()->check(CLI::Range(1, 16384));
  cmd->add_option("--warmup", c->bench.warmup, "Untimed traces first")->capture_default_str()->check(CLI::NonNegativeNumber);
  cmd->add_option("--reps", c->bench.repetitions, "Timed traces")->capture_default_str()->check(CLI::PositiveNumber);
  cmd->add_option("--json", c->json_path, "Also write every raw figure as JSON");
  cmd->add_flag("--quiet", c->quiet, "No progress display");
  return [c] { return bench(*c); };
}

} // namespace masq::cli
