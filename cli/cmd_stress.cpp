// `masq stress`: the numerical stress suite (docs/robustness.md).
#include "cli/commands.h"
#include "cli/device_option.h"
#include "host/backend.h"
#include "masq/error.h"
#include "stress/stress_report.h"
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <fstream>

namespace masq::cli {

namespace {
struct StressCli {
  stress::StressOptions opt;
  std::vector<std::string> types;
  std::vector<std::string> modes;
  std::vector<std::string> curve_isects;
  std::string nodes;
  std::string json_path;
  std::string device; // --device (cli/device_option.h)
  bool quiet = false;
  bool check = false;
};

int stress_run(StressCli& c) {
  if (!c.types.empty()) {
    c.opt.sweep.types.clear();
    for (const std::string& t : c.types) c.opt.sweep.types.push_back(parse_prim_type(t));
  }
  if (!c.curve_isects.empty()) {
    c.opt.sweep.curve_isects.clear();
    for (const std::string& n : c.curve_isects) c.opt.sweep.curve_isects.push_back(parse_curve_isect(n));
  }
  if (!c.nodes.empty()) c.opt.nodes = parse_node_format(c.nodes);
  if (!c.modes.empty()) {
    c.opt.modes.clear();
    for (const std::string& m : c.modes) c.opt.modes.push_back(parse_mode(m));
  }
  if (!c.quiet) c.opt.progress = [](const std::string& line) { fmt::print(stderr, "\r\033[K  {}", line); };
  fmt::print("stress: {} rays per cell, {} sweep, node format {}, long-double oracle; rays with oracle clearance "
             "below 4u(1+(D+L)/r) are ambiguous (counted, not compared)\n",
             c.opt.sweep.rays_per_cell, c.opt.sweep.quick ? "quick" : "full", node_format_name(c.opt.nodes));
  stress::StressReport r = stress::run_stress(c.opt);
  if (!c.quiet) fmt::print(stderr, "\r\033[K");
  for (const auto& [b, why] : r.unavailable) fmt::print("{} unavailable: {}\n", b, why);
  for (Mode m : c.opt.modes) fmt::print("\n{}", stress::stress_matrix(r, m));
  fmt::print("\nby ray kind (disagreement rate, all cells, all backends, both methods):\n{}",
             stress::stress_by_kind(r));
  fmt::print("\nsummary (rate over compared rays; culls: masq misses where ref hits, same backend and mode{}; "
             "self: surface-start rays re-hitting their origin):\n{}",
             c.opt.nodes == NodeFormat::W4 ? "" : ", and ref's misses where the w4 ref hits",
             stress::stress_summary(r));
  fmt::print("oracle {:.1f} s, total {:.1f} s\n", r.oracle_seconds, r.total_seconds);
  if (!c.json_path.empty()) {
    std::ofstream f(c.json_path);
    if (!f) throw Error("stress: cannot write " + c.json_path);
    f << stress::stress_json(r).dump(1) << "\n";
    fmt::print("wrote {}\n", c.json_path);
  }
  if (c.check) {
    fmt::print("acceptance (robust): rate <= 1e-4 per cell, 0 false culls, 0 self hits, every primitive type\n");
    std::string fails = stress::stress_failures(r);
    if (!fails.empty()) {
      fmt::print("robust-mode acceptance FAILED:\n{}", fails);
      return 1;
    }
    fmt::print("robust-mode acceptance met on every cell\n");
  }
  return 0;
}
} // namespace

Action add_stress(CLI::App& app) {
  auto c = std::make_shared<StressCli>();
  CLI::App* cmd = app.add_subcommand("stress", "Numerical stress suite: every primitive x backend x mode vs the long-double oracle");
  cmd->add_option("--rays", c->opt.sweep.rays_per_cell, "Rays per cell")->capture_default_str()->check(CLI::Range(16, 1 << 24));
  cmd->add_flag("--quick", c->opt.sweep.quick, "Fewer sweep points (the ctest subset)");
  cmd->add_option("--prim", c->types, "Primitive types (default: all): " + prim_type_table.help())
      ->check(CLI::IsMember(prim_type_table.accepted_names()));
  cmd->add_option("--sweep", c->opt.sweep.sweeps,
                  "Sweeps (default: all): " + fmt::format("{}", fmt::join(stress::sweep_names(), ", ")))
      ->check(CLI::IsMember(stress::sweep_names()));
  cmd->add_option("--backend", c->opt.backends, "Backends (default: all): " + backend_table.help())
      ->check(CLI::IsMember(backend_table.names()));
  add_device_option(*cmd, c->device);
  cmd->add_option("--mode", c->modes, "Modes (default: all): " + mode_table.help())
      ->check(CLI::IsMember(mode_table.names()));
  cmd->add_option("--curve-isect", c->curve_isects, "Curve cells, one per intersector (default: all): " + curve_isect_table.help())
      ->check(CLI::IsMember(curve_isect_table.names()));
  cmd->add_option("--nodes", c->nodes,
                  "Node format of every structure: " + node_format_table.help() +
                      " (o4 rotates every BLAS node; with any format but w4, ref's false culls are counted against the w4 ref)")
      ->check(CLI::IsMember(node_format_table.names()));
  cmd->add_option("--seed", c->opt.sweep.seed, "Random seed")->capture_default_str();
  cmd->add_option("--json", c->json_path, "Write every figure as JSON to this file");
  cmd->add_flag("--check", c->check, "Exit 1 unless robust mode meets the acceptance bounds on every cell");
  cmd->add_flag("-q,--quiet", c->quiet, "No progress line");
  cmd->footer("Examples:\n  masq stress --quick\n  masq stress --prim curve --backend cpu --rays 4096\n"
              "  masq stress --json stress.json --check\n"
              "  masq stress --quick --backend vulkan --device 0\n"
              "  masq stress --quick --nodes o4      # every BLAS node rotated: 0 false culls expected\n"
              "  masq stress --prim capsule --sweep length camera --backend cpu --mode robust");
  return [c] {
    apply_device_option(c->device, c->opt.backends.empty() ? backend_names() : c->opt.backends);
    return stress_run(*c);
  };
}

} // namespace masq::cli
