// The results document: machine and driver description, then every suite's method,
// tables and images, as bench/results/RESULTS.md plus results.json with every raw
// figure. scripts/results.sh regenerates both (and the plots) with one command.
#pragma once
#include "bench/suite.h"
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace masq {

// CPU, memory, OS, compiler, date, git commit, and each backend's device and driver.
nlohmann::json machine_description(BackendPool& pool, const std::vector<std::string>& backends);

struct ResultsRun {
  std::string command;  // how the document was made
  bool quick = false;
  double seconds = 0;   // whole run
};

// Writes out_dir/RESULTS.md and out_dir/results.json.
void write_results(const std::string& out_dir, const std::vector<SuiteResult>& suites, const nlohmann::json& machine,
                   const ResultsRun& run);

} // namespace masq
