// The results document: machine and driver description, then every suite's method,
// tables and images, as bench/results/RESULTS.md plus results.json with every raw
// figure. scripts/results.sh regenerates both (and the plots) with one command.
#pragma once
#include "bench/suite.h"
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace masq {

// results.json names its format and version, so that `masq report` (bench/report_read.h)
// can refuse a file it would misread. Version 1 (no "format" field) had no tables;
// version 2 added "format", "format_version", "masq_version" and each suite's "tables"
// and "method". Raise the version when a field changes meaning or goes away.
inline constexpr const char* results_format = "masq-results";
inline constexpr int results_format_version = 2;

// CPU, memory, OS, compiler, date, git commit, and each backend's device and driver.
nlohmann::json machine_description(BackendPool& pool, const std::vector<std::string>& backends);

struct ResultsRun {
  std::string command;  // how the document was made
  bool quick = false;
  double seconds = 0;   // whole run
};

// Writes `text` to out_dir/name (out_dir made if missing); throws masq::Error
// "<who>: cannot write '<path>'" when it cannot. The results and report documents use it.
void write_document(const std::string& out_dir, const std::string& name, const std::string& text, const char* who);

// Writes out_dir/RESULTS.md and out_dir/results.json.
void write_results(const std::string& out_dir, const std::vector<SuiteResult>& suites, const nlohmann::json& machine,
                   const ResultsRun& run);

} // namespace masq
