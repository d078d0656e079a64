// The bench harness's own logic: secondary ray sets, the RT cost model and its fit,
// tables, and one real suite run (fig3 quick on cpu) whose figures must be consistent
// with the counters it measured.
#include "bench/bench_report.h"
#include "bench/price_fit.h"
#include "bench/ray_sets.h"
#include "bench/report_fit.h"
#include "bench/rt_cost_model.h"
#include "bench/rt_fit.h"
#include "bench/suite.h"
#include "bench/table.h"
#include "scenes/camera.h"
#include "masq/error.h"
#include "scenes/generators.h"
#include <cmath>
#include <gtest/gtest.h>
#include <set>

using namespace masq;

namespace {

kernel::Hit hit_at(float t, int prim, glm::vec3 n) {
  kernel::Hit h{};
  h.t = t;
  h.prim = prim;
  h.geom = 0;
  h.inst = 0;
  h.normal[0] = n.x;
  h.normal[1] = n.y;
  h.normal[2] = n.z;
  return h;
}

Scene one_capsule_scene(float radius) {
  Scene s;
  Geometry g;
  g.type = PrimType::Capsule;
  g.capsules.push_back({{0, -1, 0}, {0, 1, 0}, radius});
  s.geometries.push_back(g);
  s.instances.push_back({0, {}});
  return s;
}

} // namespace

TEST(RaySets, ShadowRaysStartOffTheSurfaceAndEndAtTheLight) {
  Scene s = one_capsule_scene(0.01f);
  std::vector<kernel::Ray> primary = {make_ray({0.5, 0, -5}, {0, 0, 1}), make_ray({0.005, 0, -5}, {0, 0, 1})};
  std::vector<kernel::Hit> hits = {kernel::Hit{}, hit_at(5.0f - 0.0087f, 0, {0.5f, 0, -0.87f})};
  hits[0].prim = -1; // a miss spawns nothing
  std::vector<kernel::Ray> shadow = make_secondary_rays(RaySet::Shadow, s, primary, hits);
  ASSERT_EQ(shadow.size(), 1u);
  const kernel::Ray& r = shadow[0];
  glm::dvec3 end = glm::dvec3(r.org[0], r.org[1], r.org[2]) + double(r.tmax) * glm::dvec3(r.dir[0], r.dir[1], r.dir[2]);
  glm::dvec3 light = shadow_light(s.camera);
  EXPECT_LT(glm::length(end - light), 1e-5 * glm::length(light));
  // tmin * |d| = r / 16: clear of the surface, far inside the primitive's size.
  double len = glm::length(glm::dvec3(r.dir[0], r.dir[1], r.dir[2]));
  EXPECT_NEAR(double(r.tmin) * len, 0.01 / 16.0, 1e-7);
}

TEST(RaySets, DiffuseRaysLeaveOnTheSideTheRayCameFrom) {
  Scene s = one_capsule_scene(0.01f);
  std::vector<kernel::Ray> primary;
  std::vector<kernel::Hit> hits;
  for (int i = 0; i < 256; ++i) {
    primary.push_back(make_ray({0.0, 0, -5}, {0, 0, 1}));
    // Half the normals face away from the ray: the bounce must flip them.
    hits.push_back(hit_at(4.99f, 0, i % 2 ? glm::vec3(0, 0, -1) : glm::vec3(0, 0, 1)));
  }
  std::vector<kernel::Ray> diffuse = make_secondary_rays(RaySet::Diffuse, s, primary, hits, 7);
  ASSERT_EQ(diffuse.size(), 256u);
  double mean_cos = 0;
  for (const kernel::Ray& r : diffuse) {
    EXPECT_LT(r.dir[2], 0.0f); // back towards the camera side
    EXPECT_GT(r.tmin, 0.0f);
    mean_cos += -r.dir[2];
  }
  // Cosine-weighted: E[cos] = 2/3.
  EXPECT_NEAR(mean_cos / 256.0, 2.0 / 3.0, 0.05);
  // Deterministic from the seed.
  std::vector<kernel::Ray> again = make_secondary_rays(RaySet::Diffuse, s, primary, hits, 7);
  EXPECT_EQ(again[17].dir[0], diffuse[17].dir[0]);
  EXPECT_THROW(parse_ray_set("bounce"), Error);
}

TEST(RtCostModel, SpeedupIsTheCostRatioAndTheLabelCarriesTheError) {
  BenchRow ref, masq;
  ref.blas_nodes = 6;
  ref.isect_calls = 20;
  masq.tlas_nodes = 6;
  masq.blas_nodes = 20;
  masq.transforms = 20;
  masq.isect_calls = 0.5;
  RtCostModel m;
  m.price = {4.0, 0.5, 0.25, 0.25, 1.0, 0.0};
  // (4 + 6*0.25 + 20) / (4 + 6*0.5 + 20*0.25 + 20*0.25 + 0.5)
  EXPECT_NEAR(rt_predicted_speedup(ref, masq, m), 25.5 / 17.5, 1e-12);
  EXPECT_EQ(rt_speedup_label(1.5, m), "1.50x"); // unfitted: no error to show
  m.fitted = true;
  m.loo_median = 0.07;
  EXPECT_EQ(rt_speedup_label(1.5, m), "1.50x +-7%");
}

TEST(LinearFit, RecoversCoefficientsAndRefusesAnUndeterminedSystem) {
  std::vector<LinearRow> rows;
  for (int i = 0; i < 6; ++i) {
    double a = 1 + i, b = (i * 7) % 5, c = i * i * 0.5;
    rows.push_back({{a, b, c}, 2 * a - 3 * b + 0.5 * c, 1.0 / (1 + i)});
  }
  std::optional<std::vector<double>> p = fit_linear(rows);
  ASSERT_TRUE(p);
  EXPECT_NEAR((*p)[0], 2.0, 1e-9);
  EXPECT_NEAR((*p)[1], -3.0, 1e-9);
  EXPECT_NEAR((*p)[2], 0.5, 1e-9);
  for (LinearRow& r : rows) r.x[2] = 2 * r.x[0]; // two columns alike
  EXPECT_FALSE(fit_linear(rows));
  rows.resize(2);
  EXPECT_FALSE(fit_linear(rows)); // three terms need three rows
}

namespace {

// Synthetic fig3-like cells whose speedups the prices `p` produce exactly.
std::vector<RtCell> synthetic_cells(const std::array<double, kRtTerms>& p) {
  std::vector<RtCell> cells;
  RtCostModel m;
  m.price = p;
  for (int i = 0; i < 12; ++i) {
    double nodes = 1 + (i % 4) * 2.5, calls = 0.1 + (i * 37 % 11) * 3.0, left = 0.05 + (i % 3) * 0.1;
    RtCell c;
    c.label = "cell " + std::to_string(i);
    c.ref = {1.0, 0.0, nodes, 0.0, calls, 0.2};
    c.masq = {1.0, nodes * (1 + 0.1 * (i % 2)), calls, calls, left, 0.2};
    c.measured = rt_predicted_speedup(c.ref, c.masq, m);
    cells.push_back(c);
  }
  return cells;
}

} // namespace

TEST(RtFit, RecoversKnownPricesFromSyntheticCells) {
  const std::array<double, kRtTerms> truth = {6.0, 0.3, 0.1, 0.2, 1.0, 0.0};
  std::vector<RtCell> cells = synthetic_cells(truth);
  RtFitOptions opt;
  std::optional<RtFit> f = fit_rt_model(cells, opt, "synthetic");
  ASSERT_TRUE(f);
  for (int k = 0; k < kRtTerms; ++k) EXPECT_NEAR(f->model.price[k], truth[k], 1e-6) << rt_term_name(k);
  EXPECT_EQ(f->free_parameters, 4); // ray, tlas, blas, transform against isect = 1
  EXPECT_EQ(f->cells, 12);
  EXPECT_LT(f->model.loo_max, 1e-6); // exact data: every left-out cell is predicted exactly
  EXPECT_LT(f->price_error[RtRay], 1e-6);
  EXPECT_TRUE(f->model.fitted);
}

TEST(RtFit, LeaveOneOutPredictsEachCellWithoutIt) {
  std::vector<RtCell> cells = synthetic_cells({6.0, 0.3, 0.1, 0.2, 1.0, 0.0});
  // Disturb one cell: the fit to all cells moves, its own left-out prediction must not,
  // because that prediction comes from the other cells alone.
  RtFitOptions opt;
  opt.nonnegative = false;
  cells[5].measured *= 1.5;
  std::optional<RtFit> f = fit_rt_model(cells, opt, "synthetic");
  ASSERT_TRUE(f);
  std::vector<RtCell> rest = cells;
  rest.erase(rest.begin() + 5);
  std::optional<std::array<double, kRtTerms>> p = fit_rt_prices(rest, opt);
  ASSERT_TRUE(p);
  RtCostModel m;
  m.price = *p;
  EXPECT_NEAR(f->per_cell[5].loo, rt_predicted_speedup(cells[5].ref, cells[5].masq, m), 1e-9);
  EXPECT_NEAR(f->per_cell[5].loo, cells[5].measured / 1.5, 1e-6); // the undisturbed truth
  EXPECT_NEAR(f->per_cell[5].loo_error(), 1 / 1.5 - 1, 1e-6);
  EXPECT_GT(std::abs(f->per_cell[5].fitted - f->per_cell[5].loo), 1e-3); // the full fit saw the disturbance
}

TEST(RtFit, NonNegativeDropsATermThatWouldGoNegative) {
  // Data made with a negative transform price: the non-negative fit prices it at 0.
  std::vector<RtCell> cells = synthetic_cells({6.0, 0.3, 0.1, -0.05, 1.0, 0.0});
  RtFitOptions opt;
  std::optional<std::array<double, kRtTerms>> p = fit_rt_prices(cells, opt);
  ASSERT_TRUE(p);
  for (double v : *p) EXPECT_GE(v, 0.0);
  opt.nonnegative = false;
  p = fit_rt_prices(cells, opt);
  ASSERT_TRUE(p);
  EXPECT_NEAR((*p)[RtTransform], -0.05, 1e-6);
}

TEST(Table, MarkdownEscapesPipesAndAlignsColumns) {
  Table t;
  t.header = {"name", "value"};
  t.left_columns = 1;
  t.add({"a|b", "1.5"});
  std::string md = t.markdown();
  EXPECT_NE(md.find("| a\\|b | 1.5 |"), std::string::npos) << md;
  EXPECT_NE(md.find("|---|---:|"), std::string::npos) << md;
}

namespace {
// The quick variant of one suite, run for real on the cpu backend alone.
SuiteResult quick_on_cpu(const std::string& suite) {
  SuiteContext ctx;
  ctx.config.quick = true;
  ctx.config.backends = {"cpu"};
  std::vector<SuiteResult> out = run_suites(ctx, {suite});
  if (out.size() != 1u) throw Error("test: suite " + suite + " gave " + std::to_string(out.size()) + " results");
  return out[0];
}
} // namespace

TEST(Suites, UnknownSuiteIsAnError) {
  SuiteContext ctx;
  EXPECT_THROW(run_suites(ctx, {"fig4"}), Error);
}

// A real quick fig3 run on the cpu backend: every cell of the paper's grid measured,
// with the paper's figure beside it, and the call ratio in the table is the one the
// counters give.
TEST(Suites, Fig3QuickOnCpuMeasuresEveryCell) {
  SuiteResult out = quick_on_cpu("fig3");
  const nlohmann::json& cells = out.data["cells"];
  ASSERT_EQ(cells.size(), 16u); // the paper's 4 (N, r) columns x 4 tilts
  std::set<std::pair<int, float>> columns;
  for (const auto& c : cells) {
    columns.insert({c["n"].get<int>(), c["r"].get<float>()});
    ASSERT_TRUE(c["paper_rtx_speedup"].is_number()) << c.dump(); // every quick cell is one of the paper's
    EXPECT_GT(c["paper_rtx_speedup"].get<double>(), 1.0);
    double ref_calls = -1, masq_calls = -1;
    for (const auto& r : c["results"]) {
      ASSERT_FALSE(r.contains("unavailable")) << r.dump();
      EXPECT_GT(r["mrays_per_s"].get<double>(), 0.0);
      if (r["method"] == "ref") ref_calls = r["per_ray"]["isect_calls"].get<double>();
      if (r["method"] == "masq") masq_calls = r["per_ray"]["isect_calls"].get<double>();
    }
    ASSERT_GT(masq_calls, 0.0);
    // Tilted bundles: the OBB cull removes most calls; untilted ones have nothing to gain.
    const double tilt = c["tilt_deg"].get<double>();
    // One fat capsule (N=1, r=0.1) fills much of its AABB: a gain, but not tenfold.
    if (tilt >= 30.0) {
      EXPECT_GT(ref_calls / masq_calls, c["n"].get<int>() == 1 ? 2.0 : 10.0) << c.dump();
    } else if (tilt == 0.0) {
      EXPECT_LT(ref_calls / masq_calls, 1.5) << c.dump();
    }
  }
  // The RT model fitted to the paper's 16 cells, each with its left-out prediction.
  ASSERT_TRUE(out.data["rt_model"]["fitted"].get<bool>());
  EXPECT_EQ(out.data["rt_model"]["cells"].get<int>(), 16);
  EXPECT_EQ(out.data["rt_model"]["per_cell"].size(), 16u);
  EXPECT_GT(out.data["rt_model"]["loo_median_rel_error"].get<double>(), 0.0);
  EXPECT_EQ(columns, (std::set<std::pair<int, float>>{{1, 0.1f}, {10, 0.01f}, {100, 0.002f}, {1000, 0.002f}}));
  EXPECT_EQ(out.data["auto_target"]["cells"].get<int>(), 16); // cluster and auto ran in every cell
  // The main table's paper column and the grid in the paper's layout: no cell without
  // the paper's figure or without masq's cpu speedup.
  ASSERT_GE(out.tables.size(), 2u);
  const Table& main = out.tables[0];
  ASSERT_EQ(main.header[3], "paper RTX 8000");
  for (const auto& row : main.rows) EXPECT_NE(row[3], "-") << row[0] << " " << row[1] << " " << row[2];
  const Table& grid = out.tables[1];
  ASSERT_EQ(grid.header.size(), 6u);
  EXPECT_EQ(grid.header[2], "N=1 r=0.1");
  ASSERT_EQ(grid.rows.size(), 4u * 3u); // per tilt: paper, RT model, cpu
  for (const auto& row : grid.rows)
    for (std::size_t i = 2; i < row.size(); ++i) EXPECT_NE(row[i], "-") << row[1];
  ASSERT_EQ(grid.rows[3][1], "paper (RTX 8000)");
  EXPECT_EQ(grid.rows[3][5], "3.83x"); // the paper's tilt 15, N=1000 r=0.002
  EXPECT_EQ(grid.rows[4][1], "RT model");
  // The main table's left-out prediction and its error, beside the paper's figure.
  ASSERT_EQ(main.header[5], "RT model left out");
  for (const auto& row : main.rows) EXPECT_NE(row[6], "-") << row[0] << " " << row[1] << " " << row[2];
  EXPECT_NE(grid.notes[1].find("cpu: rank correlation with the paper over 16 cells"), std::string::npos) << grid.notes[1];
}

// Several builders in one bench run: each (backend, method, builder) gets its row with
// its own build figures, the same rays, and the builders table compares them.
TEST(Bench, BuildersSideBySide) {
  BundleParams bp;
  bp.count = 200;
  Scene scene = make_default_scene(bp);
  BenchOptions opt;
  opt.backends = {"cpu"};
  opt.methods = {Method::Ref, Method::Masq};
  opt.ray_sets = {RaySet::Primary};
  opt.builders = {Builder::Sah, Builder::Sbvh, Builder::SahReinsert};
  opt.width = 48;
  opt.height = 48;
  opt.warmup = 0;
  opt.repetitions = 1;
  std::vector<BenchRow> rows = run_bench(scene, opt);
  ASSERT_EQ(rows.size(), 6u);
  // Ordered backend, method, builder.
  const Builder want[] = {Builder::Sah, Builder::Sbvh, Builder::SahReinsert};
  for (std::size_t i = 0; i < rows.size(); ++i) {
    ASSERT_TRUE(rows[i].unavailable.empty()) << rows[i].unavailable;
    EXPECT_EQ(rows[i].method, i < 3 ? Method::Ref : Method::Masq);
    EXPECT_EQ(rows[i].builder, want[i % 3]);
    EXPECT_GT(rows[i].build.sah_cost, 0.0);
    EXPECT_EQ(rows[i].rays, rows[0].rays);
  }
  // ref's BLAS over the tilted strands is split: more references, lower BLAS SAH.
  EXPECT_GT(rows[1].build.blas_references, rows[1].build.blas_primitives);
  EXPECT_LT(rows[1].build.blas_sah_cost, rows[0].build.blas_sah_cost);
  EXPECT_EQ(rows[0].build.blas_references, rows[0].build.blas_primitives);
  Table t = bench_builders(rows);
  EXPECT_EQ(t.rows.size(), 6u);
  EXPECT_EQ(bench_row_json(rows[1])["builder"], "sbvh");
  opt.builders = {Builder::Sah};
  EXPECT_TRUE(bench_builders(run_bench(scene, opt)).rows.empty()) << "one builder: no builders table";
}

// A timed sample of a set smaller than sample_rays traces it as many times as it takes to
// reach that many rays, the row's times per trace; every row carries the process's CPU
// time per trace (the peers pilot chooses by it).
TEST(Bench, SampleRaysRepeatASmallSetAndRowsCarryCpuTime) {
  EXPECT_EQ(traces_per_sample(850, 36864), 44); // 44 x 850 = 37,400 >= 36,864 > 43 x 850
  EXPECT_EQ(traces_per_sample(36864, 36864), 1);
  EXPECT_EQ(traces_per_sample(40000, 36864), 1);
  EXPECT_EQ(traces_per_sample(850, 0), 1); // 0: each set once
  EXPECT_EQ(traces_per_sample(0, 36864), 1);
  BundleParams bp;
  bp.count = 200;
  Scene scene = make_default_scene(bp);
  BenchOptions opt;
  opt.backends = {"cpu"};
  opt.methods = {Method::Ref};
  opt.ray_sets = {RaySet::Primary, RaySet::Shadow};
  opt.width = 32;
  opt.height = 32;
  opt.warmup = 0;
  opt.repetitions = 1;
  opt.sample_rays = 4 * 32 * 32;
  std::vector<BenchRow> rows = run_bench(scene, opt);
  ASSERT_EQ(rows.size(), 2u);
  for (const BenchRow& r : rows) {
    ASSERT_TRUE(r.unavailable.empty()) << r.unavailable;
    EXPECT_GT(r.median_s, 0.0);
    EXPECT_GT(r.cpu_s, 0.0);
    EXPECT_EQ(bench_row_json(r)["cpu_seconds"].get<double>(), r.cpu_s);
  }
}

// Several node formats in one bench run: each (backend, method, format) gets its row, the
// same rays and the same hits, fewer node visits for 8-wide nodes, and the node table
// compares each format with w4.
TEST(Bench, NodeFormatsSideBySide) {
  BundleParams bp;
  bp.count = 200;
  Scene scene = make_default_scene(bp);
  BenchOptions opt;
  opt.backends = {"cpu"};
  opt.methods = {Method::Ref, Method::Masq};
  opt.ray_sets = {RaySet::Primary};
  opt.node_formats = node_format_table.values();
  const std::size_t formats = opt.node_formats.size();
  opt.width = 48;
  opt.height = 48;
  opt.warmup = 0;
  opt.repetitions = 1;
  std::vector<BenchRow> rows = run_bench(scene, opt);
  ASSERT_EQ(rows.size(), 2 * formats);
  for (std::size_t i = 0; i < rows.size(); ++i) {
    ASSERT_TRUE(rows[i].unavailable.empty()) << rows[i].unavailable;
    EXPECT_EQ(rows[i].method, i < formats ? Method::Ref : Method::Masq);
    EXPECT_EQ(rows[i].nodes, opt.node_formats[i % formats]);
    EXPECT_EQ(rows[i].rays, rows[0].rays);
    EXPECT_EQ(rows[i].hit_fraction, rows[i - i % formats].hit_fraction);
    EXPECT_GT(rows[i].build.node_bytes, 0u);
  }
  EXPECT_LT(rows[1].blas_nodes, rows[0].blas_nodes); // ref: 8-wide BLAS, fewer visits
  EXPECT_LT(rows[2].build.node_bytes, rows[0].build.node_bytes / 2); // q8: 80 B against 128 B nodes
  EXPECT_EQ(bench_node_ratios(rows).rows.size(), 2 * formats);
  EXPECT_EQ(bench_row_json(rows[2])["nodes"], "q8");
  EXPECT_EQ(bench_row_json(rows[2])["build"]["node_bytes"], rows[2].build.node_bytes);
}

// Both curve intersectors in one bench run on a curve bundle: each (method, intersector)
// gets its row on the same rays, the traversal counters are the same up to the cut-offs
// (only the intersector differs), the hits agree, and the side-by-side table names each.
TEST(Bench, CurveIntersectorsSideBySide) {
  BundleParams bp;
  bp.count = 100;
  bp.prim = PrimType::Curve;
  Scene scene = make_default_scene(bp);
  BenchOptions opt;
  opt.backends = {"cpu"};
  opt.methods = {Method::Ref, Method::Masq};
  opt.ray_sets = {RaySet::Primary};
  opt.curve_isects = {CurveIsect::Phantom, CurveIsect::Roving};
  opt.width = 48;
  opt.height = 48;
  opt.warmup = 0;
  opt.repetitions = 1;
  std::vector<BenchRow> rows = run_bench(scene, opt);
  ASSERT_EQ(rows.size(), 4u);
  for (std::size_t i = 0; i < rows.size(); ++i) {
    ASSERT_TRUE(rows[i].unavailable.empty()) << rows[i].unavailable;
    EXPECT_EQ(rows[i].method, i < 2 ? Method::Ref : Method::Masq);
    EXPECT_EQ(rows[i].curve_isect, i % 2 == 0 ? CurveIsect::Phantom : CurveIsect::Roving);
    EXPECT_EQ(rows[i].rays, rows[0].rays);
  }
  for (std::size_t i : {1u, 3u}) {
    // (a hit's t may differ in its last bits, which may move the traversal's cut-off)
    EXPECT_NEAR(rows[i].isect_calls, rows[i - 1].isect_calls, 1e-2 * rows[i - 1].isect_calls);
    EXPECT_NEAR(rows[i].blas_nodes, rows[i - 1].blas_nodes, 1e-2 * rows[i - 1].blas_nodes);
    EXPECT_NEAR(rows[i].hit_fraction, rows[i - 1].hit_fraction, 1e-3); // (ties on the silhouette)
  }
  EXPECT_GT(rows[0].hit_fraction, 0.0);
  EXPECT_EQ(method_label(rows[3]), "masq (roving)");
  EXPECT_EQ(bench_curve_isect_ratios(rows).rows.size(), 4u);
  EXPECT_EQ(bench_row_json(rows[1])["curve_isect"], "roving");
}

namespace {

// A row whose time follows given prices exactly: ns/ray = 7 + 3 node + 5 transform + 11 isect.
BenchRow priced_row(Method m, RaySet set, double nodes, double transforms, double isect) {
  BenchRow r;
  r.backend = "cpu";
  r.method = m;
  r.ray_set = set;
  r.rays = 1000;
  r.blas_nodes = nodes;
  r.transforms = transforms;
  r.isect_calls = isect;
  r.median_s = r.rays * (7.0 + 3.0 * nodes + 5.0 * transforms + 11.0 * isect) * 1e-9;
  return r;
}

} // namespace

TEST(PriceFit, RecoversExactPricesAndTheConstant) {
  std::vector<BenchRow> rows = {priced_row(Method::Ref, RaySet::Primary, 10, 1, 30),
                                priced_row(Method::Masq, RaySet::Primary, 40, 35, 2),
                                priced_row(Method::Cluster, RaySet::Primary, 8, 4, 5),
                                priced_row(Method::Ref, RaySet::Diffuse, 20, 1, 12),
                                priced_row(Method::Masq, RaySet::Diffuse, 25, 60, 1)};
  std::optional<PriceFit> f = fit_prices(rows, "cpu");
  ASSERT_TRUE(f);
  EXPECT_NEAR(f->ns_per_ray, 7.0, 1e-6);
  EXPECT_NEAR(f->ns_per_node, 3.0, 1e-6);
  EXPECT_NEAR(f->prices.transform, 5.0 / 3.0, 1e-6);
  EXPECT_NEAR(f->prices.isect, 11.0 / 3.0, 1e-6);
  EXPECT_LT(f->max_rel_error, 1e-9);
  EXPECT_LT(f->loo_max_rel_error, 1e-9); // exact rows: each left out is still predicted exactly
  EXPECT_GE(f->loo_max_rel_error, 0.0);
  EXPECT_FALSE(fit_prices(rows, "opencl")); // no rows of that backend
  rows.resize(3);
  EXPECT_FALSE(fit_prices(rows, "cpu")); // four prices need four rows
}

TEST(PriceFit, RowsReadBackFromJsonFitAsMeasured) {
  // A results.json's rows (bench_row_json) read back for `masq report --fit-prices`: the
  // fields the fit uses survive, and the RT-form fit recovers the prices the rows carry.
  std::vector<BenchRow> rows = {priced_row(Method::Ref, RaySet::Primary, 10, 1, 30),
                                priced_row(Method::Masq, RaySet::Primary, 40, 35, 2),
                                priced_row(Method::Cluster, RaySet::Primary, 8, 4, 5),
                                priced_row(Method::Ref, RaySet::Diffuse, 20, 1, 12),
                                priced_row(Method::Masq, RaySet::Diffuse, 25, 60, 1),
                                priced_row(Method::Cluster, RaySet::Diffuse, 14, 9, 7)};
  std::vector<BenchRow> back;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    BenchRow& r = rows[i];
    r.tlas_nodes = 1.0 + 0.3 * double(i * i); // a TLAS part unlike the BLAS one, so the RT form's node terms differ
    r.median_s += r.rays * 2.0 * r.tlas_nodes * 1e-9;
    back.push_back(bench_row_from_json(bench_row_json(r)));
    EXPECT_EQ(back.back().method, r.method);
    EXPECT_EQ(back.back().ray_set, r.ray_set);
    EXPECT_DOUBLE_EQ(back.back().median_s, r.median_s);
    EXPECT_DOUBLE_EQ(back.back().isect_calls, r.isect_calls);
  }
  std::optional<TimeFit> f = fit_time(back, "cpu", rt_form_terms);
  ASSERT_TRUE(f);
  ASSERT_EQ(f->ns.size(), 5u);
  EXPECT_NEAR(f->ns[0], 7.0, 1e-6);  // ray
  EXPECT_NEAR(f->ns[1], 2.0, 1e-6);  // TLAS node
  EXPECT_NEAR(f->ns[2], 3.0, 1e-6);  // BLAS node
  EXPECT_NEAR(f->ns[3], 5.0, 1e-6);  // transform
  EXPECT_NEAR(f->ns[4], 11.0, 1e-6); // intersector call
  EXPECT_LT(f->loo_max_rel_error, 1e-9);
}

TEST(PriceFit, ChoicesCountWhereTheCheapestByPriceIsSlow) {
  // Exact prices choose right everywhere; prices that ignore intersector calls choose
  // ref (fewest nodes and transforms) where masq, with 15x fewer calls, is faster.
  std::vector<BenchRow> g = {priced_row(Method::Ref, RaySet::Primary, 10, 1, 30),
                             priced_row(Method::Masq, RaySet::Primary, 12, 12, 2),
                             priced_row(Method::Cluster, RaySet::Primary, 11, 3, 25)};
  PriceFit exact;
  exact.ns_per_ray = 7;
  exact.ns_per_node = 3;
  exact.prices = {1.0, 5.0 / 3.0, 11.0 / 3.0};
  FitChoices c = fit_choices({g}, "cpu", exact);
  EXPECT_EQ(c.cells, 1);
  EXPECT_EQ(c.within, 1);
  PriceFit blind = exact;
  blind.prices.isect = 0;
  c = fit_choices({g}, "cpu", blind);
  EXPECT_EQ(c.cells, 1);
  EXPECT_EQ(c.within, 0);
}

// The bounding-volume table: every volume idea measured on every quick scene (the
// binary trees of Kallberg & Larsson and the binned-SAH AABB tree, masq's ref with AABB
// and oriented 4-wide nodes, masq and cluster), with counters and bytes.
TEST(Suites, BvQuickOnCpuMeasuresEveryBoundingVolume) {
  SuiteContext ctx;
  ctx.config.quick = true;
  ctx.config.backends = {"cpu"};
  ctx.config.data_dir = MASQ_DATA_DIR;
  std::vector<SuiteResult> runs = run_suites(ctx, {"bv"});
  ASSERT_EQ(runs.size(), 1u);
  const SuiteResult& out = runs[0];
  const nlohmann::json& scenes = out.data["scenes"];
  ASSERT_EQ(scenes.size(), 3u);
  const std::set<std::string> want = {"SCB p=0", "SCB p=0.2", "ball", "OBB", "AABB", "AABB (binned SAH)",
                                      "AABB 4-wide (ref)", "oriented 4-wide (ref o4)", "OBB per primitive (masq)",
                                      "OBB per cluster (cluster)"};
  for (const auto& sc : scenes) {
    ASSERT_FALSE(sc.contains("error")) << sc.dump();
    std::set<std::string> got;
    for (const auto& v : sc["variants"]) {
      got.insert(v["variant"].get<std::string>());
      ASSERT_TRUE(v["ok"].get<bool>()) << sc["scene"] << " " << v.dump();
      EXPECT_GT(v["n_b"].get<double>(), 0.0) << v["variant"];
      EXPECT_GT(v["n_t"].get<double>(), 0.0) << v["variant"];
      EXPECT_GT(v["bytes"].get<std::size_t>(), 0u) << v["variant"];
      EXPECT_GT(v["trace_seconds"]["cpu"].get<double>(), 0.0) << v["variant"];
    }
    EXPECT_EQ(got, want) << sc["scene"];
  }
  ASSERT_GE(out.tables.size(), 4u);
  EXPECT_NE(out.tables[3].title.find("bytes"), std::string::npos);
}

// A row's structures are found by its builder and node format, and a row of a build the
// run does not hold is an error that names it.
TEST(Suites, BenchRunFindsEachRowsStructures) {
  Scene scene = make_default_scene();
  BenchOptions opt;
  opt.backends = {"cpu"};
  opt.methods = {Method::Ref};
  opt.ray_sets = {RaySet::Primary};
  opt.width = 16;
  opt.height = 16;
  opt.repetitions = 1;
  opt.builders = {Builder::Sah, Builder::Sah4};
  BackendPool pool;
  BenchRun run = run_bench_kept(scene, opt, pool);
  ASSERT_EQ(run.rows.size(), 2u);
  for (const BenchRow& r : run.rows) {
    const PackedScene& ps = run.built_for(r).scenes.at(Method::Ref);
    EXPECT_EQ(ps.acceleration_bytes(), r.accel_bytes) << builder_name(r.builder);
  }
  EXPECT_NE(run.rows[0].accel_bytes, run.rows[1].accel_bytes); // two structures, told apart
  BenchRow other = run.rows[0];
  other.builder = Builder::Sbvh;
  try {
    run.built_for(other);
    ADD_FAILURE() << "no error for a builder the run did not build";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("sbvh"), std::string::npos) << e.what();
  }
}

// The bench keeps the same rays on every backend; a row with fewer rays than its device
// needs to be busy (Backend::fill_rays) gets a note naming the backend, device and need,
// and the JSON carries the timing parts beside the device time.
TEST(Bench, NotesRaySetsTooSmallToFillTheDevice) {
  BenchRow r;
  r.backend = "vulkan";
  r.device = "big gpu";
  r.rays = 1000;
  r.median_s = r.min_s = r.max_s = 0.001;
  r.wall_s = 0.003;
  r.upload_s = 0.0005;
  r.readback_s = 0.0007;
  r.fill_rays = 1000000;
  auto has_note = [](const Table& t) {
    for (const std::string& n : t.notes)
      if (n.find("too small to fill the device: vulkan on big gpu") != std::string::npos &&
          n.find("1000000") != std::string::npos)
        return true;
    return false;
  };
  EXPECT_TRUE(has_note(bench_table({r})));
  const nlohmann::json j = bench_row_json(r);
  EXPECT_EQ(j["wall_seconds"], 0.003);
  EXPECT_EQ(j["upload_seconds"], 0.0005);
  EXPECT_EQ(j["readback_seconds"], 0.0007);
  EXPECT_EQ(j["fill_rays"], 1000000);
  r.rays = 2e6;
  EXPECT_FALSE(has_note(bench_table({r})));
  r.fill_rays = 0; // the device does not say: no note
  r.rays = 10;
  EXPECT_FALSE(has_note(bench_table({r})));
}
