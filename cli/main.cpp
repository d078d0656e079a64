// masq: portable ray tracing of long, thin primitives. See `masq --help`.
#include "cli/commands.h"
#include <cstdio>
#include <exception>

int main(int argc, char** argv) {
  CLI::App app{"masq: ray tracing of long, thin primitives with the masquerade method, "
               "on cpu, vulkan, opencl and Vulkan ray query"};
  app.footer("Examples:\n"
             "  masq info\n"
             "  masq bench                          # default bundle scene, every backend x method\n"
             "  masq bench --backend cpu --method masq --width 256 --height 256\n"
             "  masq bench --prim curve --subdiv 4 --mode fast\n"
             "  masq render --backend vulkan --out bundle   # bundle_shaded.png, bundle_heat.png\n"
             "  masq stress --quick                 # numerical stress suite vs the long-double oracle\n"
             "  masq report a/results.json b/results.json   # several runs side by side, a column per device\n"
             "Every subcommand's --help shows its own examples (masq bench --help).\n"
             "Exit codes: 0 ok; 1 runtime error, one line on stderr (bad scene file, device or driver\n"
             "failure, `info` finding no backend, `stress --check` bounds missed,\n"
             "a `report` input that is not a results.json of this version); 2 usage error\n"
             "(unknown subcommand, option or value; the message names it).");
  app.require_subcommand(1);
  masq::cli::Action action;
  masq::cli::Action info = masq::cli::add_info(app);
  masq::cli::Action render = masq::cli::add_render(app);
  masq::cli::Action bench = masq::cli::add_bench(app);
  masq::cli::Action stress = masq::cli::add_stress(app);
  masq::cli::Action report = masq::cli::add_report(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    int rc = app.exit(e);
    return rc == 0 ? 0 : 2;
  }
  try {
    if (app.got_subcommand("info")) return info();
    if (app.got_subcommand("render")) return render();
    if (app.got_subcommand("bench")) return bench();
    if (app.got_subcommand("stress")) return stress();
    if (app.got_subcommand("report")) return report();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "masq: %s\n", e.what());
    return 1;
  }
  return 2;
}
