// masq bench: one scene through every backend x method with the same rays.
#include "bench/bench_report.h"
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
};

int bench(BenchCli& c) {
  Scene scene = make_scene(c.scene);
  c.bench.accel = accel_options(c.scene);
  if (!c.backends.empty()) c.bench.backends = c.backends;
  if (!c.methods.empty()) {
    c.bench.methods.clear();
    for (const std::string& m : c.methods) c.bench.methods.push_back(parse_method(m));
  }
  if (!c.quiet) c.bench.progress = [](const std::string& line) { fmt::print(stderr, "\r\033[K  {}", line); };
  fmt::print("scene '{}': {} primitives ({} {} strands r={} tilt {} deg + ground plane), {} mode, {}x{} primary rays, "
             "{} warm-up + {} timed traces, median (min-max) of device time\n",
             scene.name, scene.primitive_count(), c.scene.bundle.count, c.scene.prim, c.scene.bundle.radius,
             c.scene.bundle.tilt_deg, c.scene.mode, c.bench.width, c.bench.height, c.bench.warmup, c.bench.repetitions);
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
  cmd->add_option("--backend", c->backends, "Backends to run (default: all)")->check(CLI::IsMember({"cpu", "vulkan", "opencl", "rayquery"}));
  cmd->add_option("--method", c->methods, "Methods to run (default: ref masq)")->check(CLI::IsMember({"ref", "masq"}));
  cmd->add_option("--width", c->bench.width, "Rays per row")->capture_default_str()->check(CLI::Range(1, 16384));
  cmd->add_option("--height", c->bench.height, "Rows of rays")->capture_default_str()->check(CLI::Range(1, 16384));
  cmd->add_option("--warmup", c->bench.warmup, "Untimed traces first")->capture_default_str()->check(CLI::NonNegativeNumber);
  cmd->add_option("--reps", c->bench.repetitions, "Timed traces")->capture_default_str()->check(CLI::PositiveNumber);
  cmd->add_option("--json", c->json_path, "Also write every raw figure as JSON");
  cmd->add_flag("--quiet", c->quiet, "No progress display");
  return [c] { return bench(*c); };
}

} // namespace masq::cli
