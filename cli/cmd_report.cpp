// masq report: several bench runs' results.json merged into one document, one column
// per device (bench/report_merge.h; docs/bench.md, "Several machines and devices").
#include "bench/report_doc.h"
#include "bench/report_fit.h"
#include "bench/report_read.h"
#include "cli/commands.h"
#include "masq/error.h"
#include <fmt/format.h>
#include <fstream>
#include <map>
#include <memory>

namespace masq::cli {

namespace {
struct ReportCli {
  std::vector<std::string> files;
  std::string out_dir = "report";
  std::vector<std::string> labels; // FILE=NAME
  bool fit_prices = false;
};

// --fit-prices: each run's on-device price fit with its leave-one-out error, printed.
int fit_prices_of(const ReportCli& c) {
  for (const std::string& f : c.files) {
    std::ifstream in(f);
    if (!in) throw Error("report: cannot read " + f);
    nlohmann::json doc = nlohmann::json::parse(in);
    fmt::print("{}\n", price_fit_table(doc, "price fit of " + f).text());
  }
  return 0;
}

int report(const ReportCli& c) {
  if (c.fit_prices) return fit_prices_of(c);
  std::map<std::string, std::string> labels;
  for (const std::string& l : c.labels) {
    auto eq = l.rfind('=');
    if (eq == std::string::npos || eq == 0 || eq + 1 == l.size())
      throw Error("report: --label '" + l + "': expected FILE=NAME");
    labels[l.substr(0, eq)] = l.substr(eq + 1);
  }
  std::string command = "masq report";
  for (const std::string& f : c.files) command += " " + f;
  for (const std::string& l : c.labels) command += " --label " + l;
  if (c.out_dir != "report") command += " --out " + c.out_dir;
  MergedReport merged = merge_runs(read_results_files(c.files, labels));
  write_report(c.out_dir, merged, command);
  fmt::print("wrote {0}/RESULTS.md and {0}/report.json ({1} runs, {2} device columns) (plots: /usr/bin/python3 "
             "scripts/plot_report.py {0})\n",
             c.out_dir, merged.runs.size(), merged.devices.size());
  return 0;
}
} // namespace

Action add_report(CLI::App& app) {
  auto c = std::make_shared<ReportCli>();
  CLI::App* cmd = app.add_subcommand(
      "report", "Merge the results.json of several bench runs (machines, devices) into one RESULTS.md, a column per device");
  cmd->add_option("runs", c->files, "results.json files written by masq bench --suite (format version 2)")->required();
  cmd->add_option("--out", c->out_dir, "Output directory of RESULTS.md and report.json")->capture_default_str();
  cmd->add_option("--label", c->labels, // one FILE=NAME per --label: the run files may follow it
                  "FILE=NAME: name a run (default: its file's folder name); a column's label gets it where two "
                  "devices would be named alike")
      ->allow_extra_args(false);
  cmd->add_flag("--fit-prices", c->fit_prices,
                "Instead: per run and backend, the price fit of its fig3/table1 rows with leave-one-out errors "
                "(bench/report_fit.h)");
  cmd->footer("Examples:\n"
              "  masq report runs/*/results.json --out report          one column per backend of each run\n"
              "  masq report a/results.json b/results.json --label a/results.json=laptop\n"
              "  bash scripts/report.sh runs/*/results.json --out report   the same, then the plots");
  return [c] { return report(*c); };
}

} // namespace masq::cli
