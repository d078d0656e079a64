// Reading the results.json of bench runs for `masq report` (bench/report_merge.h): each
// file checked against the format bench/results_doc.h writes, every failure one
// masq::Error naming the file (and the JSON pointer of a bad field).
#pragma once
#include "bench/table.h"
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace masq {

struct ReportSuite {
  std::string name;   // "fig3"
  std::string title;
  std::string method; // how it was measured
  std::vector<Table> tables;
};

// One bench run: its machine, how it ran and its suites' tables.
struct ReportRun {
  std::string file;   // as given
  std::string label;  // tells runs apart: --label FILE=NAME, else the file's folder name
  nlohmann::json machine; // bench/results_doc.h machine_description
  std::map<std::string, std::string> backends; // backend -> device and driver
  std::string command;  // how it ran
  bool quick = false;
  std::string masq_version;
  std::vector<ReportSuite> suites; // in the file's order
};

// Reads and checks one results.json. label "" : the file's parent folder's name.
ReportRun read_results_file(const std::string& file, const std::string& label = "");

// Reads every file, in order: at least one, none twice (the same file by another path
// included), labels from `labels` (file -> name, the file as given or any path to it),
// and labels that repeat told apart by a number.
std::vector<ReportRun> read_results_files(const std::vector<std::string>& files,
                                          const std::map<std::string, std::string>& labels = {});

} // namespace masq
