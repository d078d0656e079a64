// The merged report as a document: DIR/RESULTS.md (devices, then each suite's merged
// tables with the geometric mean of each device's ratios) and DIR/report.json (the same
// tables and ratios, read by scripts/plot_report.py).
#pragma once
#include "bench/report_merge.h"
#include <nlohmann/json.hpp>
#include <string>

namespace masq {

// report.json names its format too, for the plot script and any later reader.
inline constexpr const char* report_format = "masq-report";
inline constexpr int report_format_version = 1;

// The image scripts/plot_report.py draws for a suite: its first table with ratios.
std::string report_plot_file(const std::string& suite);

std::string report_markdown(const MergedReport& report, const std::string& command);
nlohmann::json report_json(const MergedReport& report, const std::string& command);

// Writes out_dir/RESULTS.md and out_dir/report.json.
void write_report(const std::string& out_dir, const MergedReport& report, const std::string& command);

} // namespace masq
