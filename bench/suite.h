// The bench suites that reproduce the source papers' tables and figures (fig3, table1,
// table2, fig9, fig10, error) and measure masq against its peers (peers). Every suite
// returns tables (terminal and Markdown), its raw figures as JSON and the images it
// wrote; bench/results_doc.h assembles them into the results document.
#pragma once
#include "bench/backend_pool.h"
#include "bench/bench_runner.h"
#include "bench/rt_cost_model.h"
#include "bench/table.h"
#include "masq/names.h"
#include <functional>
#include <nlohmann/json.hpp>
#include <array>
#include <string>
#include <vector>

namespace masq {

struct SuiteConfig {
  bool quick = false;                 // the small variant: fewer cells, scenes and rays (docs/results.md: run time)
  std::string data_dir;               // ../shared/data (hair, meshes, ...)
  std::string out_dir;                // images are written here ("" : none)
  std::vector<std::string> backends = backend_names();
  Mode mode = Mode::Robust;
  AutoBy auto_by = AutoBy::Pilot;     // how the auto rows keep a candidate (bench/bench_runner.h)
  // The node format every suite builds (`--nodes` with one value): w8 comes nearer the
  // wide hardware BVH of the paper's RTX 8000 than the default w4 (docs/methods.md).
  NodeFormat nodes = NodeFormat::W4;
  std::function<void(const std::string&)> progress; // may be empty
};

struct SuiteImage {
  std::string file;    // relative to out_dir
  std::string caption;
};

struct SuiteResult {
  std::string name;        // "fig3"
  std::string title;       // a heading
  std::string method;      // how it was measured, one paragraph
  std::vector<Table> tables;
  std::vector<SuiteImage> images;
  nlohmann::json data;     // every raw figure
  double seconds = 0;
};

// One table1 scene x intersector, measured on every backend x method x ray set.
struct HairCase {
  std::string scene;    // "bear fur (TressFX 3)"
  std::string variant;  // "capsule", "link", "phantom x4"
  std::string stands_for; // the masquerade paper's Table 1 model this scene stands for ("": none)
  std::size_t primitives = 0;
  std::vector<BenchRow> rows;
  // Table 2: total bytes (primitives + acceleration data) of ref, masq and cluster per
  // node format (w4, w8, q8), from builds only.
  std::array<std::array<std::size_t, 3>, 3> total_bytes{};
};

// Shared by the suites of one run: backends opened once, the RT cost model (its prices
// fitted to the paper's Fig. 3 when fig3 runs first), and the hair measurements
// that table1, table2, fig9 and fig10 all read.
struct SuiteContext {
  SuiteConfig config;
  BackendPool pool;
  RtCostModel rt_model; // fitted by fig3 when fig3 runs first (bench/rt_paper_fit.h)
  std::vector<HairCase> hair;       // filled by collect_hair_measurements
  bool hair_timed = false;          // hair holds timings (table1), not only counters
  void say(const std::string& line) const {
    if (config.progress) config.progress(line);
  }
  BenchOptions bench_options(int width, int height) const; // quick/full repetitions
};

// The suites, in the order they run.
struct SuiteRow {
  const char* name;
  const char* help;
};
inline constexpr SuiteRow suite_rows[] = {
    {"fig3", "the masquerade paper's Fig. 3: synthetic bundles"},
    {"table1", "its Table 1: hair and fur, rays/s"},
    {"table2", "its Table 2: memory"},
    {"fig9", "its Fig. 9: AABB vs OBB surface area"},
    {"fig10", "its Fig. 10: intersector calls"},
    {"error", "run time against error of the curve intersectors"},
    {"peers", "masq's best CPU-side tracer against Embree 3, round by round"},
    {"bv", "every bounding volume: Kallberg & Larsson's slab-cut-ball, ball, OBB and AABB trees beside masq's wide AABB and oriented (o4) nodes, masq's and cluster's OBBs"},
};
inline constexpr NameTable suite_table{"suite", suite_rows};
const std::vector<std::string>& suite_names(); // suite_table's names
// Runs the named suites in a fixed order (fig3 first: it calibrates the RT model).
std::vector<SuiteResult> run_suites(SuiteContext& ctx, const std::vector<std::string>& names);

// fig3's scene: N parallel capsules (length 1, radius r, bundle radius 0.5) tilted by
// `tilt` degrees in the x-y plane, seen by an orthographic camera along +z.
Scene fig3_bundle_scene(int n, float r, double tilt);
SuiteResult run_fig3(SuiteContext& ctx);
void collect_hair_measurements(SuiteContext& ctx, bool timed); // table1's scenes x intersectors
SuiteResult table1_result(const SuiteContext& ctx);
SuiteResult table2_result(const SuiteContext& ctx);
SuiteResult fig9_result(const SuiteContext& ctx);
SuiteResult fig10_result(SuiteContext& ctx);
SuiteResult run_error_suite(SuiteContext& ctx);
SuiteResult run_peers(SuiteContext& ctx);
SuiteResult run_bv_suite(SuiteContext& ctx);

} // namespace masq
