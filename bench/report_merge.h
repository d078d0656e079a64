// `masq report`: several bench runs' tables merged into one, with one column per device
// (docs/bench.md, "Several machines and devices"). A table's label columns stay once and
// its rows are matched by them; each run's per-backend column becomes one column per
// device; shared columns stay once where the runs agree, else one per run.
#pragma once
#include "bench/report_read.h"
#include <optional>
#include <string>
#include <vector>

namespace masq {

// One backend of one run: a column of the merged tables.
struct ReportDevice {
  std::size_t run = 0;  // index into the runs
  std::string backend;  // "vulkan"
  std::string device;   // the run's device and driver string
  std::string label;    // "vulkan · NVIDIA RTX A4000", with the run's label where two would be alike
};

struct MergedTable {
  Table table;
  // Per device column: its index in table.header and its device (index into the devices).
  std::vector<std::pair<std::size_t, std::size_t>> device_columns;
  // Per device column, per row: the cell's first ratio ("1.06x"), if any.
  std::vector<std::vector<std::optional<double>>> ratios;
  // Per device column: the geometric mean of its ratios (none: no ratio in the column).
  std::vector<std::optional<double>> geomeans;
  // The same for each column that holds one run's cells of a column shared by its
  // backends (the runs disagreed on it): its index and its run (index into the runs).
  // The peers suite's masq/Embree ratios are such columns.
  std::vector<std::pair<std::size_t, std::size_t>> run_columns;
  std::vector<std::vector<std::optional<double>>> run_ratios;
  std::vector<std::optional<double>> run_geomeans;
  bool has_ratios() const;
};

struct MergedSuite {
  std::string name, title;
  // How each run that has the suite measured it (its run index and text): the counts
  // in the text ("faster on 4 of 27 rows") are that run's.
  std::vector<std::pair<std::size_t, std::string>> methods;
  std::vector<std::size_t> missing_in; // runs without this suite
  std::vector<MergedTable> tables;
};

struct MergedReport {
  std::vector<ReportRun> runs;
  std::vector<ReportDevice> devices; // those with a column in some merged table, by run then backend
  std::vector<MergedSuite> suites;   // in suite_rows order, then any other in the order first seen
};

MergedReport merge_runs(std::vector<ReportRun> runs);

// "<backend> · <device up to the first ' (' or ' ['>" (the cpu backend: the machine's CPU).
std::string device_short_name(const std::string& backend, const std::string& device, const std::string& cpu);

// The first "<number>x" in a cell ("5.33 -> 5.65 (1.06x)" -> 1.06), if any.
std::optional<double> first_ratio(const std::string& cell);

} // namespace masq
