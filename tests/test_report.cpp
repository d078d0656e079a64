// masq report: two synthetic runs merged (columns, labels, '-' cells, geometric means,
// a suite one run lacks), every kind of bad input refused naming the file, and a round
// trip through the real writer (write_results) and reader.
#include "bench/report_doc.h"
#include "bench/report_merge.h"
#include "bench/report_read.h"
#include "bench/results_doc.h"
#include "masq/error.h"
#include <filesystem>
#include <fstream>
#include <gtest/gtest.h>
#include <unistd.h>

using namespace masq;
using nlohmann::json;
namespace fs = std::filesystem;

namespace {

// A fresh folder per test, removed afterwards.
struct TempDir {
  fs::path path;
  TempDir() {
    path = fs::temp_directory_path() /
           ("masq_test_report_" + std::to_string(getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(path);
    fs::create_directories(path);
  }
  ~TempDir() { fs::remove_all(path); }
  // Writes text to path/name (folders made) and returns the file's path.
  std::string write(const std::string& name, const std::string& text) const {
    fs::path p = path / name;
    fs::create_directories(p.parent_path());
    std::ofstream(p) << text;
    return p.string();
  }
};

json table_json(std::vector<std::vector<std::string>> rows, const std::string& rt_model_n1) {
  for (auto& r : rows)
    if (r[0] == "1") r[3] = rt_model_n1;
  return {{"title", "speedup masq/ref per backend"},
          {"header", {"N", "r", "paper", "RT model", "cpu", "vulkan"}},
          {"rows", rows},
          {"notes", {"each backend: speedup / call ratio", "paper: the paper's Fig. 3"}},
          {"left_columns", 2}};
}

// A results.json of format version 2 with backends cpu and vulkan.
json results(const std::string& cpu, const std::string& vulkan_device, const json& fig3_table, bool with_table2) {
  json doc = {{"format", results_format},
              {"format_version", results_format_version},
              {"masq_version", "0.1.0"},
              {"machine",
               {{"cpu", cpu},
                {"hardware_threads", 8},
                {"memory", "16777216 kB"},
                {"os", "Linux"},
                {"date", "2026-11-26 12:00 UTC"},
                {"git_commit", "abc1234"},
                {"backends", {{"cpu", "kernel source as C++, 8 threads"}, {"vulkan", vulkan_device}}}}},
              {"run", {{"command", "masq bench --suite fig3 --quick"}, {"quick", true}, {"seconds", 1.0}}},
              {"suites", {{"fig3", {{"title", "Fig. 3"}, {"seconds", 1.0}, {"data", json::object()},
                                    {"tables", {fig3_table}}}}}}};
  if (with_table2)
    doc["suites"]["table2"] = {{"title", "Table 2"}, {"seconds", 0.0}, {"data", json::object()},
                               {"tables", {{{"title", "bytes"}, {"header", {"scene", "cpu"}},
                                            {"rows", json::array({json::array({"bear", "1.5x"})})}, {"notes", json::array()},
                                            {"left_columns", 1}}}}};
  return doc;
}

// Two machines: a has rows N=1, 10, 100 and table2; b has N=1, 10, 1000 and a different RT model at N=1.
struct TwoRuns {
  TempDir dir;
  std::string a, b;
  TwoRuns() {
    a = dir.write("a/results.json",
                  results("AMD EPYC", "llvmpipe (LLVM 15.0.6, 256 bits) [Mesa 25.0.7]",
                          table_json({{"1", "0.1", "1.05x", "", "2.00x / 1.0x", "0.50x / 1.0x"},
                                      {"10", "0.01", "1.03x", "2.35x", "8.00x / 13.2x", "2.00x / 13.2x"},
                                      {"100", "0.002", "2.01x", "3.68x", "1.00x / 84x", "1.00x / 84x"}},
                                     "0.93x"),
                          true)
                      .dump());
    b = dir.write("b/results.json",
                  results("Intel Xeon", "NVIDIA RTX A4000 [NVIDIA 550.54]",
                          table_json({{"1", "0.1", "1.05x", "", "3.00x / 1.0x", "4.00x / 1.0x"},
                                      {"10", "0.01", "1.03x", "2.35x", "3.00x / 13.2x", "1.00x / 13.2x"},
                                      {"1000", "0.002", "3.83x", "3.83x", "1.20x / 84x", "9.00x / 84x"}},
                                     "0.95x"),
                          false)
                      .dump());
  }
};

const MergedTable& fig3_table(const MergedReport& r) {
  EXPECT_EQ(r.suites.at(0).name, "fig3");
  return r.suites.at(0).tables.at(0);
}

std::vector<std::string> row_of(const Table& t, const std::string& n) {
  for (const auto& row : t.rows)
    if (row.at(0) == n) return row;
  ADD_FAILURE() << "no row N=" << n;
  return {};
}

// The message of the masq::Error that reading `files` throws ("" if none).
std::string read_error(const std::vector<std::string>& files) {
  try {
    read_results_files(files);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

} // namespace

TEST(Report, DeviceColumnsLabelsAndSharedColumns) {
  TwoRuns runs;
  MergedReport r = merge_runs(read_results_files({runs.a, runs.b}));
  ASSERT_EQ(r.devices.size(), 4u);
  EXPECT_EQ(r.devices[0].label, "cpu · AMD EPYC");
  EXPECT_EQ(r.devices[1].label, "vulkan · llvmpipe");
  EXPECT_EQ(r.devices[2].label, "cpu · Intel Xeon");
  EXPECT_EQ(r.devices[3].label, "vulkan · NVIDIA RTX A4000");
  const Table& t = fig3_table(r).table;
  // paper agrees: once; RT model differs at N=1: once per run; each backend: once per run.
  std::vector<std::string> header = {"N", "r", "paper", "RT model (a)", "RT model (b)", "cpu · AMD EPYC",
                                     "cpu · Intel Xeon", "vulkan · llvmpipe", "vulkan · NVIDIA RTX A4000"};
  EXPECT_EQ(t.header, header);
  EXPECT_EQ(t.left_columns, 2);
  ASSERT_EQ(t.rows.size(), 4u);
  // b's new row follows a's rows; each run's own order kept.
  EXPECT_EQ(t.rows[2][0], "100");
  EXPECT_EQ(t.rows[3][0], "1000");
  EXPECT_EQ(row_of(t, "1"), (std::vector<std::string>{"1", "0.1", "1.05x", "0.93x", "0.95x", "2.00x / 1.0x",
                                                       "3.00x / 1.0x", "0.50x / 1.0x", "4.00x / 1.0x"}));
  // A row one run lacks: '-' in that run's columns, the shared columns from the other.
  EXPECT_EQ(row_of(t, "100"), (std::vector<std::string>{"100", "0.002", "2.01x", "3.68x", "-", "1.00x / 84x", "-",
                                                         "1.00x / 84x", "-"}));
  EXPECT_EQ(row_of(t, "1000"), (std::vector<std::string>{"1000", "0.002", "3.83x", "-", "3.83x", "-", "1.20x / 84x",
                                                          "-", "9.00x / 84x"}));
  EXPECT_EQ(t.notes, (std::vector<std::string>{"each backend: speedup / call ratio", "paper: the paper's Fig. 3"}));
}

TEST(Report, GeometricMeansAndMissingSuite) {
  TwoRuns runs;
  MergedReport r = merge_runs(read_results_files({runs.a, runs.b}));
  const MergedTable& t = fig3_table(r);
  ASSERT_EQ(t.device_columns.size(), 4u);
  ASSERT_TRUE(t.geomeans[0]);
  EXPECT_NEAR(*t.geomeans[0], std::cbrt(2.0 * 8.0 * 1.0), 1e-9); // cpu on a: 2, 8, 1 ('-' row skipped)
  EXPECT_NEAR(*t.geomeans[3], std::cbrt(4.0 * 1.0 * 9.0), 1e-9); // vulkan on b
  ASSERT_EQ(r.suites.size(), 2u);
  EXPECT_EQ(r.suites[1].name, "table2");
  EXPECT_EQ(r.suites[1].missing_in, std::vector<std::size_t>{1});
  std::string md = report_markdown(r, "masq report a b");
  EXPECT_NE(md.find("## Devices"), std::string::npos);
  EXPECT_NE(md.find("geometric mean of the first ratio per cell, cpu · AMD EPYC: 2.52x over 3 rows"), std::string::npos)
      << md;
  EXPECT_NE(md.find("Not in b (`" + runs.b + "`)"), std::string::npos) << md;
  EXPECT_NE(md.find("](report_fig3.png)"), std::string::npos);
  EXPECT_LT(md.find("## Fig. 3"), md.find("## Table 2"));
  json j = report_json(r, "masq report a b");
  EXPECT_EQ(j["format"], report_format);
  EXPECT_EQ(j["suites"][0]["plot"], "report_fig3.png");
  EXPECT_EQ(j["suites"][0]["plot_table"], 0);
  EXPECT_EQ(j["suites"][0]["tables"][0]["device_columns"][1]["device"], "cpu · Intel Xeon");
  EXPECT_EQ(j["suites"][0]["tables"][0]["device_columns"][1]["ratios"][0], 3.0);
  EXPECT_TRUE(j["suites"][0]["tables"][0]["device_columns"][1]["ratios"][2].is_null()); // N=100: not on b
}

// A peers-like table: scene and rays name the row, the tracer the pilot chose and the
// ratios are the run's. `narrowed`: written since the peers table declares two label
// columns (label_columns 2); else as before (three left columns, no label_columns).
json peers_suite(const std::string& method, const std::vector<std::vector<std::string>>& rows, bool narrowed) {
  json t = {{"title", "masq's tracer against Embree 3"},
            {"header", {"scene", "rays", "masq (pilot's choice)", "masq/Embree CPU time"}},
            {"rows", rows},
            {"notes", json::array()},
            {"left_columns", 3}};
  if (narrowed) t["label_columns"] = 2;
  return {{"title", "Peers"}, {"method", method}, {"seconds", 1.0}, {"data", json::object()}, {"tables", {t}}};
}

TEST(Report, PeersRowsMatchOnSceneAndRaysWhateverTracerEachRunChose) {
  TempDir dir;
  json a = results("AMD EPYC", "llvmpipe", table_json({}, ""), false);
  a["suites"] = {{"peers", peers_suite("faster on 0 of 2 rows",
                                       {{"bear", "primary", "cpu ref", "0.50x (0.40-0.60)"},
                                        {"bear", "shadow (any)", "cpu ref w8", "0.80x (0.70-0.90)"}},
                                       false)}};
  json b = a;
  b["suites"] = {{"peers", peers_suite("faster on 1 of 2 rows",
                                       {{"bear", "primary", "cpu ref w8", "2.00x (1.50-2.50)"},
                                        {"bear", "shadow (any)", "cpu ref w8", "0.80x (0.75-0.85)"}},
                                       true)}};
  std::string fa = dir.write("before/results.json", a.dump()), fb = dir.write("after/results.json", b.dump());
  MergedReport r = merge_runs(read_results_files({fa, fb}));
  ASSERT_EQ(r.suites.at(0).name, "peers");
  const MergedTable& m = r.suites[0].tables.at(0);
  // One row per scene and ray set, though the runs chose other tracers for the first.
  EXPECT_EQ(m.table.header, (std::vector<std::string>{"scene", "rays", "masq (pilot's choice) (before)",
                                                      "masq (pilot's choice) (after)",
                                                      "masq/Embree CPU time (before)", "masq/Embree CPU time (after)"}));
  ASSERT_EQ(m.table.rows.size(), 2u);
  EXPECT_EQ(m.table.rows[0], (std::vector<std::string>{"bear", "primary", "cpu ref", "cpu ref w8", "0.50x (0.40-0.60)",
                                                       "2.00x (1.50-2.50)"}));
  EXPECT_EQ(m.table.label_columns, 2);
  EXPECT_EQ(m.table.left_columns, 4); // the labels and each run's tracer names
  // Each run's ratio column has its geometric mean; the tracer columns hold none.
  ASSERT_EQ(m.run_columns.size(), 2u);
  EXPECT_EQ(m.run_columns[0], (std::pair<std::size_t, std::size_t>{4, 0}));
  EXPECT_EQ(m.run_columns[1], (std::pair<std::size_t, std::size_t>{5, 1}));
  EXPECT_NEAR(*m.run_geomeans[0], std::sqrt(0.5 * 0.8), 1e-9);
  EXPECT_NEAR(*m.run_geomeans[1], std::sqrt(2.0 * 0.8), 1e-9);
  // Each run's own account of how it measured (its counts), after its label.
  std::string md = report_markdown(r, "masq report before after");
  EXPECT_NE(md.find("- **before:** faster on 0 of 2 rows\n- **after:** faster on 1 of 2 rows"), std::string::npos) << md;
  EXPECT_NE(md.find("geometric mean of the first ratio per cell, masq/Embree CPU time (after): 1.26x over 2 rows"),
            std::string::npos)
      << md;
  json j = report_json(r, "masq report before after");
  EXPECT_EQ(j["suites"][0]["tables"][0]["run_columns"][1]["run"], "after");
}

TEST(Report, AlikeDevicesGetTheRunLabel) {
  TempDir dir;
  json t = table_json({{"1", "0.1", "1.05x", "", "2.00x", "1.00x"}}, "0.93x");
  std::string a = dir.write("x/results.json", results("AMD EPYC", "llvmpipe (LLVM 15)", t, false).dump());
  std::string b = dir.write("y/results.json", results("AMD EPYC", "llvmpipe (LLVM 15)", t, false).dump());
  MergedReport r = merge_runs(read_results_files({a, b}, {{b, "second"}}));
  ASSERT_EQ(r.devices.size(), 4u);
  EXPECT_EQ(r.devices[0].label, "cpu · AMD EPYC (x)");
  EXPECT_EQ(r.devices[2].label, "cpu · AMD EPYC (second)");
  EXPECT_EQ(r.devices[3].label, "vulkan · llvmpipe (second)");
  // Two files in folders of one name: the second run's label gets a number.
  std::string c = dir.write("z/x/results.json", results("Intel Xeon", "NVIDIA", t, false).dump());
  EXPECT_EQ(read_results_files({a, c})[1].label, "x 2");
}

TEST(Report, ShortNamesAndRatios) {
  EXPECT_EQ(device_short_name("vulkan", "llvmpipe (LLVM 15.0.6, 256 bits) [Mesa 25]", "AMD EPYC"), "vulkan · llvmpipe");
  EXPECT_EQ(device_short_name("rayquery", "NVIDIA RTX A4000 [NVIDIA 550]", ""), "rayquery · NVIDIA RTX A4000");
  EXPECT_EQ(device_short_name("cpu", "kernel source as C++, 2 threads", "AMD EPYC 7B13"), "cpu · AMD EPYC 7B13");
  EXPECT_EQ(device_short_name("opencl", "unavailable: no platform", ""), "opencl · unavailable");
  EXPECT_EQ(first_ratio("5.33 -> 5.65 (1.06x)"), 1.06);
  EXPECT_EQ(first_ratio("3.31x / 1.0x"), 3.31);
  EXPECT_EQ(first_ratio("0.27x / 0.90x (masq)"), 0.27);
  EXPECT_FALSE(first_ratio("phantom x8"));
  EXPECT_FALSE(first_ratio("96x96 rays"));
  EXPECT_FALSE(first_ratio("ref 1.4, masq 1.29"));
  EXPECT_FALSE(first_ratio("-"));
}

TEST(Report, BadInputNamesTheFile) {
  TwoRuns runs;
  auto expect_error = [&](const std::vector<std::string>& files, const std::string& file, const std::string& part) {
    std::string e = read_error(files);
    EXPECT_NE(e.find(file), std::string::npos) << e;
    EXPECT_NE(e.find(part), std::string::npos) << "expected '" << part << "' in: " << e;
  };
  std::string missing = (runs.dir.path / "none/results.json").string();
  expect_error({missing}, missing, "no such file");
  std::string not_json = runs.dir.write("bad.json", "{\"format\": masq");
  expect_error({not_json}, not_json, "not JSON (byte ");
  std::string other = runs.dir.write("other.json", "{\"name\": \"something else\"}");
  expect_error({other}, other, "not a masq results file");
  json v1 = results("AMD EPYC", "llvmpipe", table_json({}, ""), false);
  v1.erase("format");
  v1.erase("format_version");
  v1["run"]["command"] = "masq bench --suite all --quick";
  std::string old = runs.dir.write("old.json", v1.dump());
  expect_error({old}, old, "a masq results file of format version 1");
  expect_error({old}, old, "rerun `masq bench --suite all --quick` with this masq");
  json v3 = results("AMD EPYC", "llvmpipe", table_json({}, ""), false);
  v3["format_version"] = 3;
  std::string newer = runs.dir.write("newer.json", v3.dump());
  expect_error({newer}, newer, "format version 3");
  json bad_rows = results("AMD EPYC", "llvmpipe", table_json({}, ""), false);
  bad_rows["suites"]["fig3"]["tables"][0]["rows"] = "none";
  std::string ill = runs.dir.write("ill.json", bad_rows.dump());
  expect_error({ill}, ill, "/suites/fig3/tables/0/rows: not an array");
  json bad_cell = results("AMD EPYC", "llvmpipe", table_json({{"1", "0.1", "", "", "1x", "1x"}}, ""), false);
  bad_cell["suites"]["fig3"]["tables"][0]["rows"][0][4] = 2.5;
  std::string cell = runs.dir.write("cell.json", bad_cell.dump());
  expect_error({cell}, cell, "/suites/fig3/tables/0/rows/0/4: not a string");
  json no_backends = results("AMD EPYC", "llvmpipe", table_json({}, ""), false);
  no_backends["machine"].erase("backends");
  std::string nb = runs.dir.write("nb.json", no_backends.dump());
  expect_error({nb}, nb, "/machine/backends: missing");
  json quick_text = results("AMD EPYC", "llvmpipe", table_json({}, ""), false);
  quick_text["run"]["quick"] = "yes";
  std::string qt = runs.dir.write("qt.json", quick_text.dump());
  expect_error({qt}, qt, "/run/quick: not true or false");
  expect_error({}, "", "no results files given");
  expect_error({runs.a, runs.b, runs.a}, runs.a, "given twice");
  std::string other_path = (runs.dir.path / "b" / ".." / "a" / "results.json").string();
  expect_error({runs.a, other_path}, other_path, "given twice (as " + runs.a + ")");
  EXPECT_THROW(merge_runs({}), Error);
  EXPECT_THROW(read_results_files({runs.a}, {{"elsewhere.json", "x"}}), Error);
}

// The real writer and reader: two runs of write_results, merged.
TEST(Report, RoundTripThroughWriteResults) {
  TempDir dir;
  auto run = [&](const std::string& name, const std::string& device, const std::string& speedup, bool extra_row) {
    SuiteResult s;
    s.name = "fig3";
    s.title = "Fig. 3: synthetic bundles";
    s.method = "tiny bundles";
    Table t;
    t.title = "speedup masq/ref per backend";
    t.header = {"N", "RT model", "vulkan", "vulkan calls/ray"};
    t.left_columns = 0; // numbers aligned right, as fig3's; N still names the row
    t.label_columns = 1;
    if (extra_row) t.add({"10", "2.35x", "2.00x", "0.5 -> 0.1 (5.0x)"}); // first: rows match by N, not by place
    t.add({"1", "0.93x", speedup, "0.43 -> 0.25 (1.8x)"});
    t.notes = {"a note"};
    s.tables = {t};
    s.data = {{"cells", json::array({1, 2})}};
    json machine = {{"cpu", "AMD EPYC"}, {"hardware_threads", 2}, {"memory", "24684092 kB"},
                    {"os", "Debian"}, {"date", "2026-11-26"}, {"git_commit", "61e9975"},
                    {"backends", {{"vulkan", device}}}};
    std::string out = (dir.path / name).string();
    write_results(out, {s}, machine, ResultsRun{"masq bench --suite fig3 --quick", true, 2.0});
    return out + "/results.json";
  };
  std::string a = run("lavapipe", "llvmpipe (LLVM 15.0.6) [Mesa]", "1.10x", false);
  std::string b = run("gpu", "NVIDIA H100 [NVIDIA 550]", "3.00x", true);
  json written = json::parse(std::ifstream(a));
  EXPECT_EQ(written["format"], results_format);
  EXPECT_EQ(written["format_version"], results_format_version);
  EXPECT_TRUE(written["masq_version"].is_string());
  EXPECT_EQ(written["suites"]["fig3"]["data"]["cells"].size(), 2u); // plot_results.py's input unchanged
  EXPECT_EQ(written["suites"]["fig3"]["tables"][0]["header"][3], "vulkan calls/ray");
  MergedReport r = merge_runs(read_results_files({a, b}));
  const Table& t = fig3_table(r).table;
  EXPECT_EQ(t.header, (std::vector<std::string>{"N", "RT model", "vulkan · llvmpipe", "vulkan · NVIDIA H100",
                                                "vulkan · llvmpipe calls/ray", "vulkan · NVIDIA H100 calls/ray"}));
  EXPECT_EQ(written["suites"]["fig3"]["tables"][0]["label_columns"], 1);
  ASSERT_EQ(t.rows.size(), 2u);
  EXPECT_EQ(t.label_columns, 1);
  EXPECT_EQ(t.rows[0], (std::vector<std::string>{"10", "2.35x", "-", "2.00x", "-", "0.5 -> 0.1 (5.0x)"})); // b's order
  EXPECT_EQ(t.rows[1], (std::vector<std::string>{"1", "0.93x", "1.10x", "3.00x", "0.43 -> 0.25 (1.8x)",
                                                 "0.43 -> 0.25 (1.8x)"}));
  EXPECT_EQ(r.suites[0].methods, (std::vector<std::pair<std::size_t, std::string>>{{0, "tiny bundles"}, {1, "tiny bundles"}}));
  std::string out = (dir.path / "report").string();
  write_report(out, r, "masq report");
  EXPECT_TRUE(fs::exists(out + "/RESULTS.md"));
  json report = json::parse(std::ifstream(out + "/report.json"));
  EXPECT_EQ(report["devices"].size(), 2u);
  EXPECT_EQ(report["runs"][1]["label"], "gpu");
}
