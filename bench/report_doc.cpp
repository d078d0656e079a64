#include "bench/report_doc.h"
#include "bench/results_doc.h"
#include "masq/error.h"
#include "masq/masq.h"
#include <algorithm>
#include <fmt/format.h>
#include <optional>
#include <sstream>
#include <vector>

namespace masq {

namespace {

// "24684092 kB" (/proc/meminfo) as "23.5 GiB"; anything else as it is.
std::string memory_text(const std::string& meminfo) {
  std::size_t end = 0;
  try {
    double kb = std::stod(meminfo, &end);
    if (meminfo.substr(end) == " kB") return fmt::format("{:.1f} GiB", kb / (1024.0 * 1024.0));
  } catch (const std::exception&) {
  }
  return meminfo;
}

// The first table of a suite whose device columns hold ratios: the one plotted.
const MergedTable* plotted_table(const MergedSuite& s) {
  for (const MergedTable& t : s.tables)
    if (t.has_ratios()) return &t;
  return nullptr;
}

std::string runs_text(const MergedReport& report, const std::vector<std::size_t>& runs) {
  std::string out;
  for (std::size_t r : runs)
    out += (out.empty() ? "" : ", ") + report.runs[r].label + " (`" + report.runs[r].file + "`)";
  return out;
}

// How the suite was measured: once where every run says the same, else each run's text
// after its label (its counts, "faster on 4 of 27 rows", are its own).
std::string methods_text(const MergedReport& report, const MergedSuite& s) {
  if (s.methods.empty()) return "";
  const bool alike = std::all_of(s.methods.begin(), s.methods.end(),
                                 [&](const auto& m) { return m.second == s.methods.front().second; });
  if (alike) return s.methods.front().second + "\n\n";
  std::string out;
  for (const auto& [run, text] : s.methods) out += "- **" + report.runs[run].label + ":** " + text + "\n";
  return out + "\n";
}

// "- geometric mean of the first ratio per cell, <column>: 1.06x over 27 rows" (nothing
// for a column without a ratio).
std::string geomean_line(const std::string& column, const std::vector<std::optional<double>>& ratios,
                         const std::optional<double>& geomean) {
  if (!geomean) return "";
  int rows = int(std::count_if(ratios.begin(), ratios.end(), [](const auto& v) { return v && *v > 0; }));
  return "- geometric mean of the first ratio per cell, " + column + ": " + fmt::format("{:.2f}x", *geomean) +
         " over " + std::to_string(rows) + (rows == 1 ? " row" : " rows") + "\n";
}

// A table's ratio columns as JSON: per column its index, its device's or run's name (under
// `name_key`), each row's first ratio (null: none) and their geometric mean.
nlohmann::json ratio_columns_json(const char* name_key, const std::vector<std::pair<std::size_t, std::size_t>>& columns,
                                  const std::vector<std::string>& names,
                                  const std::vector<std::vector<std::optional<double>>>& ratios,
                                  const std::vector<std::optional<double>>& geomeans) {
  using nlohmann::json;
  json out = json::array();
  for (std::size_t c = 0; c < columns.size(); ++c) {
    json cells = json::array();
    for (const auto& v : ratios[c]) cells.push_back(v ? json(*v) : json());
    out.push_back({{"column", columns[c].first},
                   {name_key, names[c]},
                   {"ratios", cells},
                   {"geomean", geomeans[c] ? json(*geomeans[c]) : json()}});
  }
  return out;
}

Table devices_table(const MergedReport& report) {
  Table t;
  t.header = {"column", "run", "backend", "device and driver", "CPU", "threads", "memory", "OS", "date", "commit",
              "masq", "variant", "command"};
  t.left_columns = int(t.header.size());
  for (const ReportDevice& d : report.devices) {
    const ReportRun& r = report.runs[d.run];
    const auto& m = r.machine;
    t.add({d.label, r.label + " (`" + r.file + "`)", d.backend, d.device, m.value("cpu", ""),
           m.contains("hardware_threads") ? m["hardware_threads"].dump() : "", memory_text(m.value("memory", "")),
           m.value("os", ""), m.value("date", ""), m.value("git_commit", ""), r.masq_version,
           r.quick ? "quick" : "full", "`" + r.command + "`"});
  }
  return t;
}

} // namespace

std::string report_plot_file(const std::string& suite) { return "report_" + suite + ".png"; }

std::string report_markdown(const MergedReport& report, const std::string& command) {
  std::ostringstream md;
  md << "# masq benchmark results: " << report.runs.size() << " runs side by side\n\n";
  md << "Merged by `" << command << "` (masq " << api::version() << ") from ";
  std::vector<std::size_t> all;
  for (std::size_t r = 0; r < report.runs.size(); ++r) all.push_back(r);
  md << runs_text(report, all) << ". Do not edit by hand: rerun the command.\n\n";
  md << "Each device column is one backend of one run. A ratio (masq/ref, masq/Embree) was measured within one run on "
        "one device, on the same rays, so ratios compare across devices; absolute rays/s compare only as far as the "
        "machines were quiet. Label columns and the columns the runs agree on appear once; a row one run lacks shows "
        "`-` in that run's columns; a shared column the runs disagree on appears once per run.\n\n";
  md << "## Devices\n\n" << devices_table(report).markdown() << "\n";
  for (const MergedSuite& s : report.suites) {
    md << "## " << s.title << " (`" << s.name << "`)\n\n";
    if (!s.missing_in.empty()) md << "Not in " << runs_text(report, s.missing_in) << ": that run did not run this suite.\n\n";
    md << methods_text(report, s);
    for (const MergedTable& t : s.tables) {
      md << t.table.markdown() << "\n";
      if (!t.has_ratios() && t.run_columns.empty()) continue;
      for (std::size_t c = 0; c < t.device_columns.size(); ++c)
        md << geomean_line(report.devices[t.device_columns[c].second].label, t.ratios[c], t.geomeans[c]);
      for (std::size_t c = 0; c < t.run_columns.size(); ++c)
        md << geomean_line(t.table.header[t.run_columns[c].first], t.run_ratios[c], t.run_geomeans[c]);
      md << "\n";
    }
    if (const MergedTable* p = plotted_table(s))
      md << "![" << p->table.title << ", per device](" << report_plot_file(s.name) << ")\n\n*" << p->table.title
         << ": one bar per device (scripts/plot_report.py)*\n\n";
  }
  return md.str();
}

nlohmann::json report_json(const MergedReport& report, const std::string& command) {
  using nlohmann::json;
  json j;
  j["format"] = report_format;
  j["format_version"] = report_format_version;
  j["masq_version"] = api::version();
  j["command"] = command;
  j["runs"] = json::array();
  for (const ReportRun& r : report.runs)
    j["runs"].push_back({{"file", r.file}, {"label", r.label}, {"masq_version", r.masq_version},
                         {"command", r.command}, {"quick", r.quick}, {"machine", r.machine}});
  j["devices"] = json::array();
  for (const ReportDevice& d : report.devices)
    j["devices"].push_back({{"label", d.label}, {"run", d.run}, {"backend", d.backend}, {"device", d.device}});
  j["suites"] = json::array();
  for (const MergedSuite& s : report.suites) {
    json suite = {{"name", s.name}, {"title", s.title}, {"missing_in", s.missing_in}, {"tables", json::array()}};
    const MergedTable* plotted = plotted_table(s);
    suite["plot"] = plotted ? json(report_plot_file(s.name)) : json();
    for (const MergedTable& t : s.tables) {
      json table = t.table;
      std::vector<std::string> devices, runs;
      for (const auto& [column, device] : t.device_columns) devices.push_back(report.devices[device].label);
      for (const auto& [column, run] : t.run_columns) runs.push_back(report.runs[run].label);
      table["device_columns"] = ratio_columns_json("device", t.device_columns, devices, t.ratios, t.geomeans);
      table["run_columns"] = ratio_columns_json("run", t.run_columns, runs, t.run_ratios, t.run_geomeans);
      if (&t == plotted) suite["plot_table"] = suite["tables"].size();
      suite["tables"].push_back(table);
    }
    j["suites"].push_back(suite);
  }
  return j;
}

void write_report(const std::string& out_dir, const MergedReport& report, const std::string& command) {
  write_document(out_dir, "RESULTS.md", report_markdown(report, command), "report");
  write_document(out_dir, "report.json", report_json(report, command).dump(1) + "\n", "report");
}

} // namespace masq
