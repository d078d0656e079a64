#include "bench/report_merge.h"
#include "bench/suite.h"
#include "masq/error.h"
#include <algorithm>
#include <cctype>
#include <cmath>
#include <map>
#include <set>

namespace masq {

namespace {

// The union of several sequences in the order first seen: a key new in a later sequence
// goes right before the next key of that sequence already placed (at the end if none),
// so each run's order survives the merge and a later run's new columns or rows follow
// the earlier runs' ones at the same place.
std::vector<std::string> merged_order(const std::vector<std::vector<std::string>>& sequences) {
  std::vector<std::string> out;
  std::set<std::string> placed;
  for (const auto& seq : sequences) {
    const std::set<std::string> placed_before(placed);
    for (std::size_t i = 0; i < seq.size(); ++i) {
      if (placed.count(seq[i])) continue;
      auto next = std::find_if(seq.begin() + std::ptrdiff_t(i) + 1, seq.end(),
                               [&](const std::string& k) { return placed_before.count(k) > 0; });
      auto at = next == seq.end() ? out.end() : std::find(out.begin(), out.end(), *next);
      out.insert(at, seq[i]);
      placed.insert(seq[i]);
    }
  }
  return out;
}

// Keys that repeat in one sequence ("" in a continuation row's label cell) get their
// occurrence number, so the n-th of them matches the n-th in another run.
std::vector<std::string> numbered(const std::vector<std::string>& keys) {
  std::map<std::string, int> seen;
  std::vector<std::string> out;
  for (const std::string& k : keys) out.push_back(k + '\x1e' + std::to_string(seen[k]++));
  return out;
}

// The run's backend this column header belongs to: the header itself ("vulkan") or its
// first word ("rayquery calls/ray ..."); "" for a label or shared column.
std::string backend_of(const std::string& header, const ReportRun& run) {
  std::string best;
  for (const auto& [backend, device] : run.backends)
    if ((header == backend || header.rfind(backend + " ", 0) == 0) && backend.size() > best.size()) best = backend;
  return best;
}

// One run's copy of a table, indexed for the merge.
struct TableSource {
  std::size_t run = 0;
  const Table* table = nullptr;
  std::vector<std::string> column_keys;          // numbered headers
  std::map<std::string, std::size_t> row_of_key; // numbered label values -> row
  std::vector<std::string> row_keys;

  std::optional<std::size_t> column(const std::string& key) const {
    auto it = std::find(column_keys.begin(), column_keys.end(), key);
    if (it == column_keys.end()) return std::nullopt;
    return std::size_t(it - column_keys.begin());
  }
  const std::vector<std::string>* row(const std::string& key) const {
    auto it = row_of_key.find(key);
    return it == row_of_key.end() ? nullptr : &table->rows[it->second];
  }
};

TableSource index_table(std::size_t run, const Table& t, const std::vector<std::string>& label_headers) {
  TableSource s{run, &t, numbered(t.header), {}, {}};
  std::vector<std::optional<std::size_t>> label_columns;
  for (const std::string& h : numbered(label_headers)) label_columns.push_back(s.column(h));
  std::vector<std::string> keys;
  for (const auto& row : t.rows) {
    std::string key;
    for (const auto& c : label_columns) key += (c ? Table::cell(row, *c) : std::string()) + '\x1f';
    keys.push_back(key);
  }
  s.row_keys = numbered(keys);
  for (std::size_t r = 0; r < s.row_keys.size(); ++r) s.row_of_key[s.row_keys[r]] = r;
  return s;
}

// Column i's first ratio per row, and their geometric mean (none: no positive ratio).
struct ColumnRatios {
  std::vector<std::optional<double>> ratios;
  std::optional<double> geomean;
};
ColumnRatios column_ratios(const Table& t, std::size_t i) {
  ColumnRatios c;
  double log_sum = 0;
  int count = 0;
  for (const auto& row : t.rows) {
    c.ratios.push_back(first_ratio(row[i]));
    if (c.ratios.back() && *c.ratios.back() > 0) {
      log_sum += std::log(*c.ratios.back());
      ++count;
    }
  }
  if (count) c.geomean = std::exp(log_sum / count);
  return c;
}

using DeviceIndex = std::map<std::pair<std::size_t, std::string>, std::size_t>; // (run, backend) -> device

// label_count: how many leading columns name a row in every source (merge_runs).
MergedTable merge_table(const std::vector<TableSource>& sources, std::size_t label_count,
                        const std::vector<ReportRun>& runs, const std::vector<ReportDevice>& devices,
                        const DeviceIndex& device_of) {
  const Table& first = *sources.front().table;
  std::vector<std::vector<std::string>> column_orders, row_orders, note_orders;
  for (const TableSource& s : sources) {
    column_orders.push_back(s.column_keys);
    row_orders.push_back(s.row_keys);
    note_orders.push_back(s.table->notes);
  }
  const std::vector<std::string> columns = merged_order(column_orders);
  const std::vector<std::string> rows = merged_order(row_orders);
  const std::vector<std::string>& first_keys = sources.front().column_keys;
  const std::vector<std::string> label_keys(first_keys.begin(), first_keys.begin() + std::ptrdiff_t(label_count));

  // Each merged column: its header and how a row's cell is found.
  struct Column {
    std::string header;
    const TableSource* only = nullptr; // one run's column ("-" where that run lacks the row); null: any run's
    std::string key;
    std::optional<std::size_t> device;
    std::optional<std::size_t> run; // a shared column's cells of one run
  };
  std::vector<Column> out;
  std::size_t label_columns = 0; // leading label columns of the merged table
  for (const std::string& key : columns) {
    const bool label = std::find(label_keys.begin(), label_keys.end(), key) != label_keys.end();
    std::vector<const TableSource*> having;
    std::string backend, header;
    for (const TableSource& s : sources)
      if (auto c = s.column(key)) {
        having.push_back(&s);
        header = s.table->header[*c];
        if (backend.empty()) backend = backend_of(header, runs[s.run]);
      }
    if (label) {
      out.push_back({header, nullptr, key, std::nullopt, std::nullopt});
      if (out.size() == label_columns + 1) ++label_columns;
      continue;
    }
    if (!backend.empty()) { // one column per run that has it: its device
      for (const TableSource* s : having) {
        const std::string& own = s->table->header[*s->column(key)];
        std::string b = backend_of(own, runs[s->run]);
        if (b.empty()) { // this run has no such backend: its column is a shared one
          out.push_back({own + " (" + runs[s->run].label + ")", s, key, std::nullopt, s->run});
          continue;
        }
        std::size_t d = device_of.at({s->run, b});
        out.push_back({devices[d].label + own.substr(b.size()), s, key, d, std::nullopt}); // keeps " calls/ray ..."
      }
      continue;
    }
    bool agree = true; // a shared column: once if every run that has a row says the same
    for (const std::string& r : rows) {
      std::optional<std::string> seen;
      for (const TableSource* s : having)
        if (const auto* row = s->row(r)) {
          std::string v = Table::cell(*row, *s->column(key));
          if (seen && v != *seen) agree = false;
          seen = v;
        }
    }
    if (agree) {
      out.push_back({header, nullptr, key, std::nullopt, std::nullopt});
    } else {
      for (const TableSource* s : having)
        out.push_back({header + " (" + runs[s->run].label + ")", s, key, std::nullopt, s->run});
    }
  }

  MergedTable m;
  m.table.title = first.title;
  m.table.label_columns = int(label_columns);
  // Aligned left: the leading columns the first run aligns left, each run's copy of them
  // included (the peers table's tracer names, one column per run).
  const std::size_t left_count = std::min(std::size_t(std::max(first.left_columns, 0)), first_keys.size());
  const std::vector<std::string> left_keys(first_keys.begin(), first_keys.begin() + std::ptrdiff_t(left_count));
  std::size_t left = 0;
  while (left < out.size() && std::find(left_keys.begin(), left_keys.end(), out[left].key) != left_keys.end()) ++left;
  m.table.left_columns = int(left);
  m.table.notes = merged_order(note_orders);
  for (const Column& c : out) m.table.header.push_back(c.header);
  for (const std::string& r : rows) {
    std::vector<std::string> row;
    for (const Column& c : out) {
      std::string value = "-";
      for (const TableSource& s : sources) {
        if (c.only && c.only != &s) continue;
        const auto* source_row = s.row(r);
        auto column = s.column(c.key);
        if (source_row && column) {
          value = Table::cell(*source_row, *column);
          break;
        }
      }
      row.push_back(value);
    }
    m.table.rows.push_back(std::move(row));
  }
  for (std::size_t i = 0; i < out.size(); ++i) {
    if (!out[i].device && !out[i].run) continue;
    ColumnRatios c = column_ratios(m.table, i);
    if (out[i].device) {
      m.device_columns.emplace_back(i, *out[i].device);
      m.ratios.push_back(std::move(c.ratios));
      m.geomeans.push_back(c.geomean);
    } else if (c.geomean) { // a run's column without a ratio (its tracer names, rays/s) is left out
      m.run_columns.emplace_back(i, *out[i].run);
      m.run_ratios.push_back(std::move(c.ratios));
      m.run_geomeans.push_back(c.geomean);
    }
  }
  return m;
}

// Every (run, backend) with a column in some table, labelled; two alike get the run's label.
std::vector<ReportDevice> collect_devices(const std::vector<ReportRun>& runs, DeviceIndex& device_of) {
  std::vector<ReportDevice> devices;
  for (std::size_t r = 0; r < runs.size(); ++r)
    for (const ReportSuite& s : runs[r].suites)
      for (const Table& t : s.tables)
        for (std::size_t c = std::size_t(t.row_label_columns()); c < t.header.size(); ++c) {
          std::string b = backend_of(t.header[c], runs[r]);
          if (b.empty() || device_of.count({r, b})) continue;
          device_of[{r, b}] = devices.size();
          const std::string& device = runs[r].backends.at(b);
          std::string cpu = runs[r].machine.value("cpu", "");
          devices.push_back({r, b, device, device_short_name(b, device, cpu)});
        }
  std::map<std::string, int> uses;
  for (const ReportDevice& d : devices) ++uses[d.label];
  for (ReportDevice& d : devices)
    if (uses[d.label] > 1) d.label += " (" + runs[d.run].label + ")";
  return devices;
}

} // namespace

bool MergedTable::has_ratios() const {
  return std::any_of(geomeans.begin(), geomeans.end(), [](const auto& g) { return g.has_value(); });
}

std::string device_short_name(const std::string& backend, const std::string& device, const std::string& cpu) {
  std::string name = backend == "cpu" && !cpu.empty() ? cpu : device;
  name = name.substr(0, std::min(name.find(" ("), name.find(" [")));
  if (name.rfind("unavailable:", 0) == 0) name = "unavailable";
  return backend + " · " + name;
}

std::optional<double> first_ratio(const std::string& cell) {
  for (std::size_t x = cell.find('x'); x != std::string::npos; x = cell.find('x', x + 1)) {
    // A number right before the x, and no letter or digit after it ("96x96", "phantom x8" are not ratios).
    if (x + 1 < cell.size() && std::isalnum(static_cast<unsigned char>(cell[x + 1]))) continue;
    std::size_t begin = x;
    while (begin > 0 && (std::isdigit(static_cast<unsigned char>(cell[begin - 1])) || cell[begin - 1] == '.')) --begin;
    if (begin == x || !std::isdigit(static_cast<unsigned char>(cell[begin]))) continue;
    if (begin > 0 && std::isalpha(static_cast<unsigned char>(cell[begin - 1]))) continue;
    return std::stod(cell.substr(begin, x - begin));
  }
  return std::nullopt;
}

MergedReport merge_runs(std::vector<ReportRun> runs) {
  if (runs.empty()) throw Error("report: no results files given (masq report RUN/results.json ...)");
  MergedReport report;
  report.runs = std::move(runs);
  DeviceIndex device_of;
  report.devices = collect_devices(report.runs, device_of);
  std::vector<std::string> names = suite_names(); // the suite table's order, then the rest as seen
  for (const ReportRun& r : report.runs)
    for (const ReportSuite& s : r.suites)
      if (std::find(names.begin(), names.end(), s.name) == names.end()) names.push_back(s.name);
  for (const std::string& name : names) {
    std::vector<std::pair<std::size_t, const ReportSuite*>> having;
    MergedSuite merged;
    merged.name = name;
    for (std::size_t r = 0; r < report.runs.size(); ++r) {
      auto& suites = report.runs[r].suites;
      auto it = std::find_if(suites.begin(), suites.end(), [&](const ReportSuite& s) { return s.name == name; });
      if (it == suites.end()) {
        merged.missing_in.push_back(r);
        continue;
      }
      having.emplace_back(r, &*it);
      if (merged.title.empty()) merged.title = it->title;
      if (!it->method.empty()) merged.methods.emplace_back(r, it->method);
    }
    if (having.empty()) continue;
    // Tables matched by title (the n-th of one title with the n-th).
    std::vector<std::vector<std::string>> title_orders;
    for (auto& [r, s] : having) {
      std::vector<std::string> titles;
      for (const Table& t : s->tables) titles.push_back(t.title);
      title_orders.push_back(numbered(titles));
    }
    for (const std::string& title : merged_order(title_orders)) {
      // Rows are named by as many leading columns as every run's copy declares: the fewest.
      // A table whose labels were narrowed later (the peers suite's pilot choice is a run's
      // answer, not the row's name) then matches older runs' rows on the columns they share.
      std::vector<std::pair<std::size_t, const Table*>> tables; // (run, its copy of the table)
      std::vector<std::string> label_headers;
      for (std::size_t h = 0; h < having.size(); ++h) {
        auto it = std::find(title_orders[h].begin(), title_orders[h].end(), title);
        if (it == title_orders[h].end()) continue;
        const Table& t = having[h].second->tables[std::size_t(it - title_orders[h].begin())];
        if (tables.empty() || std::size_t(t.row_label_columns()) < label_headers.size())
          label_headers.assign(t.header.begin(), t.header.begin() + t.row_label_columns());
        tables.emplace_back(having[h].first, &t);
      }
      std::vector<TableSource> sources;
      for (const auto& [run, t] : tables) sources.push_back(index_table(run, *t, label_headers));
      merged.tables.push_back(merge_table(sources, label_headers.size(), report.runs, report.devices, device_of));
    }
    report.suites.push_back(std::move(merged));
  }
  return report;
}

} // namespace masq
