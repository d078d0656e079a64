// table1, table2, fig9, fig10: hair and fur scenes (the shared TressFX models and
// generated hair) x intersectors (capsule, link = round cone, phantom cubic curves with
// 1/2/4/8 pre-subdivisions), measured once and read by all four views.
#include "bench/bench_report.h"
#include "bench/driver_calls.h"
#include "bench/heatmap.h"
#include "bench/method_compare.h"
#include "bench/paper_tables.h"
#include "bench/suite.h"
#include "scenes/curve_tools.h"
#include "scenes/prim_table.h"
#include "masq/error.h"
#include "scenes/loaders/load_any.h"
#include "scenes/strand_generators.h"
#include <chrono>
#include <filesystem>
#include <fmt/format.h>

namespace masq {

namespace {

struct HairScene {
  std::string label;
  std::string file; // under data_dir; empty: generated
  HairSurface surface = HairSurface::Head;
  int strands = 0;
  // The masquerade paper's Table 1 model of the same kind (bench/paper_figures.h): its
  // models are not available here, so animal fur stands for autumn's and head hair for
  // curly hair; none of these scenes is curled like single curl or franck's wool.
  std::string stands_for;
};

std::vector<HairScene> hair_scenes(bool quick) {
  std::vector<HairScene> s = {{"bear fur (TressFX 3)", "hair/tressfx3_bear.tfx", HairSurface::Head, 0, "autumn"}};
  if (quick) return s;
  s.push_back({"Ratboy mohawk (TressFX 4)", "hair/tressfx4_Ratboy_mohawk.tfx", HairSurface::Head, 0, "curly hair"});
  s.push_back({"TestHair1 (TressFX 3)", "hair/tressfx3_TestHair1.tfx", HairSurface::Head, 0, "curly hair"});
  s.push_back({"generated hair 10k strands", "", HairSurface::Head, 10000, "curly hair"});
  s.push_back({"generated fur 40k strands", "", HairSurface::Body, 40000, "autumn"});
  return s;
}

struct Variant {
  std::string name;
  PrimType type;
  int subdivisions;
  CurveIsect curve_isect = CurveIsect::Phantom; // curves: the intersector
};

std::vector<Variant> variants(bool quick) {
  std::vector<Variant> v = {{"capsule", PrimType::Capsule, 1}, {"link", PrimType::RoundCone, 1}};
  for (int k : quick ? std::vector<int>{1, 8} : std::vector<int>{1, 2, 4, 8})
    v.push_back({fmt::format("phantom x{}", k), PrimType::Curve, k});
  // Roving capsules on the same cubics (kernels/curve_roving.h); x1 is the case the
  // phantom rows are measured against.
  v.push_back({"roving x1", PrimType::Curve, 1, CurveIsect::Roving});
  return v;
}

Scene make_case(const SuiteConfig& cfg, const HairScene& hs, const Variant& v) {
  if (hs.file.empty()) {
    HairParams hp;
    hp.strands = hs.strands;
    hp.surface = hs.surface;
    if (hs.surface == HairSurface::Body) {
      hp.points = 4;
      hp.length = 0.15;
      hp.gravity = 0.1;
    }
    hp.type = v.type;
    return subdivide_curves(make_hair_scene(hp), v.subdivisions);
  }
  LoadOptions lo;
  const ScenePrimRow& row = scene_prim_row(v.type);
  lo.strand_type = row.strand_file_type; // curves: round cones, made cubics below
  Scene s = load_scene_file((std::filesystem::path(cfg.data_dir) / hs.file).string(), lo);
  if (row.shape == PrimShape::Bezier) s = subdivide_curves(segments_to_curves(s), v.subdivisions);
  return s;
}

const BenchRow* counter_row(const HairCase& c, Method m, RaySet set) {
  for (const BenchRow& r : c.rows)
    if (r.method == m && r.ray_set == set && r.unavailable.empty() && r.tlas_nodes >= 0) return &r;
  return nullptr;
}

const BenchRow* any_row(const HairCase& c, Method m) {
  for (const BenchRow& r : c.rows)
    if (r.method == m) return &r;
  return nullptr;
}

// "12.0+3.5": per ray, what RT hardware does besides intersector calls (the fixed cost,
// node visits, transforms) + the calls, in units of one intersector call.
std::string rt_split(const BenchRow& r, const RtCostModel& m) {
  RtCounters x = rt_counters(r);
  double calls = m.price[RtIsect] * x[RtIsect];
  return fmt::format("{:.1f}+{:.1f}", rt_cost(x, m) - calls, calls);
}

// A path of the paper's Table 1 (4 paths per pixel, primary and bounce rays): a primary
// ray and, where it hits, one diffuse bounce; its counters per camera ray.
RtCounters path_counters(const BenchRow& primary, const BenchRow& diffuse) {
  RtCounters p = rt_counters(primary), d = rt_counters(diffuse);
  for (int k = 0; k < kRtTerms; ++k) p[k] += primary.hit_fraction * d[k];
  return p;
}

// The RT model's out-of-sample prediction of the paper's Table 1: each masq case that
// stands for one of its models, beside the paper's speedup for that model and intersector.
Table table1_rt_prediction(const std::vector<HairCase>& cases, const RtCostModel& model, nlohmann::json& data) {
  Table t;
  t.title = "the RT model's prediction of the paper's Table 1 (out of sample: prices fitted to Fig. 3 only)";
  t.header = {"scene", "stands for", "intersector", "paper RTX 8000", "RT model primary", "error", "RT model path",
              "error"};
  t.left_columns = 3;
  data = nlohmann::json::array();
  for (const HairCase& c : cases) {
    const PaperModel* pm = paper_model(c.stands_for);
    if (!pm) continue;
    std::size_t mi = std::size_t(pm - paper_table1_models().data());
    const PaperRate* rate = nullptr;
    for (const PaperTable1Row& p : paper_table1())
      if (c.variant == p.intersector && p.rates[mi].measured) rate = &p.rates[mi];
    const BenchRow* r = counter_row(c, Method::Ref, RaySet::Primary);
    const BenchRow* m = counter_row(c, Method::Masq, RaySet::Primary);
    if (!rate || !r || !m) continue;
    double primary = rt_predicted_speedup(*r, *m, model);
    const BenchRow* rd = counter_row(c, Method::Ref, RaySet::Diffuse);
    const BenchRow* md = counter_row(c, Method::Masq, RaySet::Diffuse);
    double path = rd && md ? rt_predicted_speedup(path_counters(*r, *rd), path_counters(*m, *md), model) : 0.0;
    t.add({c.scene, c.stands_for, c.variant, fmt::format("{:.2f}x", rate->speedup), rt_speedup_label(primary, model),
           fmt::format("{:+.0f}%", 100 * (primary / rate->speedup - 1)), path > 0 ? rt_speedup_label(path, model) : "n/a",
           path > 0 ? fmt::format("{:+.0f}%", 100 * (path / rate->speedup - 1)) : "-"});
    data.push_back({{"scene", c.scene}, {"stands_for", c.stands_for}, {"variant", c.variant},
                    {"paper_speedup", rate->speedup}, {"rt_model_primary", primary},
                    {"rt_model_path", path}});
  }
  t.notes = {rt_model_note(model),
             "primary: the cpu counters of primary rays; path: a primary ray plus, where it hits, one diffuse bounce "
             "(the paper traces 4 paths per pixel); the errors measure the model and the scene mismatch together "
             "(masq's scenes only stand for the paper's models, docs/results.md)"};
  return t;
}

std::string mib(std::size_t b) { return fmt::format("{:.2f}", b / 1048576.0); }

// Memory of ref, masq and cluster in each node format: the masquerade's overhead with
// nodes as small as they come (q8) next to the default (w4).
// {"w4": {"ref": bytes, "masq": bytes, "cluster": bytes}, "w8": ..., "q8": ...}
nlohmann::json per_format_json(const HairCase& c) {
  nlohmann::json j = nlohmann::json::object();
  const char* names[3] = {"w4", "w8", "q8"};
  for (int f = 0; f < 3; ++f) {
    const auto& b = c.total_bytes[std::size_t(f)];
    j[names[f]] = {{"ref", b[0]}, {"masq", b[1]}, {"cluster", b[2]}};
  }
  return j;
}

// The w4 sizes come from hc.rows (the suite's builds); w8 and q8 are built here.
void record_memory_per_format(const Scene& s, const AccelOptions& base, HairCase& hc) {
  const Method methods[3] = {Method::Ref, Method::Masq, Method::Cluster};
  const NodeFormat formats[3] = {NodeFormat::W4, NodeFormat::W8, NodeFormat::Q8};
  for (int m = 0; m < 3; ++m) {
    const BenchRow* r = any_row(hc, methods[m]);
    if (!r || r->nodes != NodeFormat::W4) return; // no w4 build of this method to compare with
    hc.total_bytes[0][std::size_t(m)] = r->prim_bytes + r->accel_bytes;
  }
  for (int f = 1; f < 3; ++f)
    for (int m = 0; m < 3; ++m) {
      AccelOptions o = base;
      o.nodes = formats[f];
      PackedScene ps = build_accel(s, methods[m], o);
      hc.total_bytes[std::size_t(f)][std::size_t(m)] = ps.primitive_bytes() + ps.acceleration_bytes();
    }
}

} // namespace

void collect_hair_measurements(SuiteContext& ctx, bool timed) {
  const bool quick = ctx.config.quick;
  const int w = quick ? 96 : 256, h = quick ? 72 : 192;
  BenchOptions opt = ctx.bench_options(w, h);
  opt.methods = {Method::Ref, Method::Masq, Method::Cluster, Method::Auto};
  if (!timed) {
    // Only counters and memory (table2, fig9, fig10 without table1): the cpu backend.
    opt.backends = {"cpu"};
    opt.ray_sets = {RaySet::Primary};
    opt.warmup = 0;
    opt.repetitions = 1;
  }
  ctx.hair.clear();
  ctx.hair_timed = timed;
  std::vector<HairScene> scenes = hair_scenes(quick);
  std::vector<Variant> vars = variants(quick);
  int step = 0;
  const int steps = int(scenes.size() * vars.size());
  for (const HairScene& hs : scenes) {
    for (const Variant& v : vars) {
      ++step;
      HairCase hc;
      hc.scene = hs.label;
      hc.variant = v.name;
      hc.stands_for = hs.stands_for;
      opt.progress = [&](const std::string& line) { ctx.say(fmt::format("table1 {}/{} {} {}: {}", step, steps, hs.label, v.name, line)); };
      try {
        Scene s = make_case(ctx.config, hs, v);
        hc.primitives = s.primitive_count();
        BenchOptions vo = opt;
        vo.accel.curve_isect = v.curve_isect;
        hc.rows = run_bench(s, vo, ctx.pool);
        record_memory_per_format(s, vo.accel, hc);
      } catch (const std::exception& e) {
        // A missing data file: every row of this case says why.
        BenchRow r;
        r.backend = "-";
        r.unavailable = e.what();
        hc.rows = {r};
      }
      ctx.hair.push_back(std::move(hc));
    }
  }
}

SuiteResult table1_result(const SuiteContext& ctx) {
  SuiteResult res;
  res.name = "table1";
  res.title = "Table 1: hair and fur, rays/s ref vs masq per intersector";
  std::vector<std::string> backends = ctx.config.backends;
  for (RaySet set : {RaySet::Primary, RaySet::Shadow, RaySet::Diffuse}) {
    Table t;
    t.title = fmt::format("{} rays: Mrays/s ref -> masq (speedup) per backend", ray_set_name(set));
    t.header = {"scene", "intersector", "prims"};
    for (const std::string& b : backends) t.header.push_back(b);
    t.left_columns = 2;
    for (const HairCase& c : ctx.hair) {
      std::vector<std::string> line = {c.scene, c.variant, std::to_string(c.primitives)};
      for (const std::string& b : backends) {
        const BenchRow* r = find_row(c.rows, b, Method::Ref, set);
        const BenchRow* m = find_row(c.rows, b, Method::Masq, set);
        line.push_back(r && m ? fmt::format("{:.2f} -> {:.2f} ({:.2f}x)", r->mrays_per_s(), m->mrays_per_s(),
                                            m->mrays_per_s() / r->mrays_per_s())
                              : "n/a");
      }
      if (c.rows.size() == 1 && !c.rows[0].unavailable.empty()) line = {c.scene, c.variant, "-", "unavailable: " + c.rows[0].unavailable};
      t.add(line);
    }
    res.tables.push_back(t);
  }
  Table mt;
  mt.title = "cluster and auto on the same rays";
  mt.header = {"scene", "intersector", "rays"};
  for (const std::string& b : backends) mt.header.push_back(b);
  mt.left_columns = 3;
  MethodTally tally;
  for (const HairCase& c : ctx.hair)
    for (RaySet set : {RaySet::Primary, RaySet::Shadow, RaySet::Diffuse}) {
      std::vector<std::string> line = {c.scene, c.variant, ray_set_name(set)};
      for (const std::string& b : backends) line.push_back(method_cell(c.rows, b, set, tally));
      mt.add(line);
    }
  std::vector<std::vector<BenchRow>> groups;
  for (const HairCase& c : ctx.hair) groups.push_back(c.rows);
  nlohmann::json fit;
  mt.notes = {method_note(tally), price_fit_note(groups, backends, fit)};
  res.data["price_fit"] = fit;
  res.data["auto_target"] = {{"cells", tally.cells}, {"within_5_percent", tally.auto_within}, {"worst", tally.worst},
                             {"kept_within_5_percent", tally.kept_within}, {"kept_worst", tally.kept_worst}};
  res.tables.push_back(mt);
  res.tables[2].notes = {"link = round cone (Han et al.), phantom xk = Reshetov's phantom cubic curve with each curve "
                             "pre-split into k (robust mode: the certified subdivision of the whole curve), roving x1 = "
                             "roving capsules on the same cubics (kernels/curve_roving.h); TressFX strands become "
                             "Catmull-Rom cubics through the same points",
                             "shadow: rays from the primary hits to a point light; diffuse: cosine-weighted bounces from "
                             "the primary hits (incoherent)"};
  res.tables.push_back(table1_beside_paper(ctx.hair, backends));
  Table pt = table1_rt_prediction(ctx.hair, ctx.rt_model, res.data["rt_model_prediction"]);
  if (!pt.rows.empty()) res.tables.push_back(pt);
  std::vector<DriverCallsCase> driver_cases;
  for (const HairCase& c : ctx.hair) driver_cases.push_back({{c.scene, c.variant}, &c.rows});
  Table dt = driver_calls_table("primary rays through the driver's traversal: intersector calls per ray and rays/s",
                                {"scene", "intersector"}, driver_cases, backends, RaySet::Primary,
                                res.data["driver_calls"]);
  if (!dt.rows.empty()) res.tables.push_back(dt);
  res.data["cases"] = nlohmann::json::array();
  for (const HairCase& c : ctx.hair) {
    nlohmann::json j = {{"scene", c.scene}, {"variant", c.variant}, {"primitives", c.primitives},
                        {"stands_for", c.stands_for}};
    for (const BenchRow& r : c.rows) j["results"].push_back(bench_row_json(r));
    res.data["cases"].push_back(j);
  }
  res.images.push_back({"table1_speedup.png", "Speedup masq/ref per case, backend and ray set (scripts/plot_results.py)"});
  res.method = "Each scene x intersector built once per method; the same primary, shadow and diffuse rays through every "
               "backend x method; median device time (wall time on cpu) of the timed traces after warm-up.";
  return res;
}

SuiteResult table2_result(const SuiteContext& ctx) {
  SuiteResult res;
  res.name = "table2";
  res.title = "Table 2: memory per method";
  Table t;
  t.header = {"scene", "intersector", "prims", "common MiB", "ref accel MiB", "ref total MiB", "masq accel MiB",
              "masq total MiB", "masq +%", "masq B/prim", "cluster total MiB", "cluster +%", "cluster B/prim"};
  const std::vector<std::string> driver = driver_backends(ctx.config.backends);
  for (const std::string& b : driver) {
    t.header.push_back(b + " ref MiB");
    t.header.push_back(b + " masq MiB");
  }
  t.left_columns = 2;
  for (const HairCase& c : ctx.hair) {
    const BenchRow* r = any_row(c, Method::Ref);
    const BenchRow* m = any_row(c, Method::Masq);
    const BenchRow* cl = any_row(c, Method::Cluster);
    if (!r || !m || !r->accel_bytes) continue;
    std::size_t ref_total = r->prim_bytes + r->accel_bytes, masq_total = m->prim_bytes + m->accel_bytes;
    std::vector<std::string> line = {
        c.scene, c.variant, std::to_string(c.primitives), mib(r->prim_bytes), mib(r->accel_bytes), mib(ref_total),
        mib(m->accel_bytes), mib(masq_total),
        fmt::format("+{:.0f}%", 100.0 * (double(masq_total) / double(ref_total) - 1.0)),
        fmt::format("{:.1f}", double(m->accel_bytes) / double(std::max<std::size_t>(1, c.primitives))),
        cl ? mib(cl->prim_bytes + cl->accel_bytes) : "n/a",
        cl ? fmt::format("{:+.0f}%", 100.0 * (double(cl->prim_bytes + cl->accel_bytes) / double(ref_total) - 1.0)) : "n/a",
        cl ? fmt::format("{:.1f}", double(cl->accel_bytes) / double(std::max<std::size_t>(1, c.primitives))) : "n/a"};
    nlohmann::json j = {{"scene", c.scene},
                        {"variant", c.variant},
                        {"primitives", c.primitives},
                        {"common_bytes", r->prim_bytes},
                        {"ref_accel_bytes", r->accel_bytes},
                        {"masq_accel_bytes", m->accel_bytes},
                        {"cluster_accel_bytes", cl ? cl->accel_bytes : 0},
                        {"total_bytes_per_node_format", per_format_json(c)}};
    for (const std::string& b : driver)
      for (Method method : {Method::Ref, Method::Masq}) {
        const BenchRow* d = find_row(c.rows, b, method, RaySet::Primary);
        line.push_back(d ? mib(d->device_bytes) : "n/a");
        j[b + "_" + method_name(method) + "_device_bytes"] = d ? d->device_bytes : 0;
      }
    t.add(line);
    res.data.push_back(j);
  }
  t.notes = {"common: primitive data both methods share; accel: masq's own two-level BVH (nodes, references, instances, "
             "compact masquerade entries and their owners, frames); masq +%: masq total over ref total (the paper's "
             "layout); rayquery, rtpipeline: what the driver's acceleration structures and the primitives take on the "
             "device (rtpipeline: and its shader binding table)"};
  res.tables.push_back(t);
  Table nf;
  nf.header = {"scene", "intersector", "ref w4 MiB", "masq/ref w4", "cluster/ref w4", "ref w8 MiB", "masq/ref w8",
               "cluster/ref w8", "ref q8 MiB", "masq/ref q8", "cluster/ref q8"};
  nf.left_columns = 2;
  for (const HairCase& c : ctx.hair) {
    if (c.total_bytes[0][0] == 0) continue;
    std::vector<std::string> row = {c.scene, c.variant};
    for (const auto& b : c.total_bytes) {
      row.push_back(mib(b[0]));
      row.push_back(fmt::format("{:.2f}x", double(b[1]) / double(b[0])));
      row.push_back(fmt::format("{:.2f}x", double(b[2]) / double(b[0])));
    }
    nf.add(row);
  }
  nf.notes = {"total = primitives + acceleration data, each method built in each node format (docs/kernels.md); the "
              "issue-7 targets: masq at most 1.5x ref, cluster at most 1.2x"};
  if (!nf.rows.empty()) res.tables.push_back(nf);
  res.tables.push_back(table2_beside_paper(ctx.hair));
  res.images.push_back({"memory.png", "Memory per method: common data and acceleration data (scripts/plot_results.py)"});
  res.method = "Byte counts of the packed scenes each method uploads (host-side sizes of the GPU arrays), and the device "
               "memory the rayquery and rtpipeline backends hold after the driver's acceleration-structure builds.";
  return res;
}

SuiteResult fig9_result(const SuiteContext& ctx) {
  SuiteResult res;
  res.name = "fig9";
  res.title = "Fig. 9: surface area of AABBs vs OBBs";
  Table t;
  t.header = {"scene", "intersector", "prims", "sum AABB area", "sum OBB area", "OBB/AABB"};
  t.left_columns = 2;
  for (const HairCase& c : ctx.hair) {
    const BenchRow* m = any_row(c, Method::Masq);
    if (!m || !(m->build.aabb_area > 0)) continue;
    t.add({c.scene, c.variant, std::to_string(c.primitives), fmt::format("{:.4g}", m->build.aabb_area),
           fmt::format("{:.4g}", m->build.obb_area), fmt::format("{:.3f}", m->build.obb_area / m->build.aabb_area)});
    res.data.push_back({{"scene", c.scene}, {"variant", c.variant}, {"aabb_area", m->build.aabb_area},
                        {"obb_area", m->build.obb_area}});
  }
  t.notes = {"summed over primitives: the exact world AABB of each primitive vs its masquerade OBB (fp32-verified, "
             "tight curve fit); lower is a tighter cull"};
  res.tables.push_back(t);
  res.method = "From the masq builds of table1's scenes: every primitive's exact AABB and its stored OBB.";
  return res;
}

SuiteResult fig10_result(SuiteContext& ctx) {
  SuiteResult res;
  res.name = "fig10";
  res.title = "Fig. 10: intersector calls per ray";
  Table t;
  t.header = {"scene", "intersector", "ref calls/ray", "masq calls/ray", "ref/masq"};
  const std::vector<std::string> driver = driver_backends(ctx.config.backends);
  for (const std::string& b : driver) {
    t.header.push_back(b + " ref");
    t.header.push_back(b + " masq");
  }
  for (const char* h : {"RT cost ref hw+sw", "RT cost masq hw+sw", "RT model speedup"}) t.header.push_back(h);
  t.left_columns = 2;
  for (const HairCase& c : ctx.hair) {
    const BenchRow* r = counter_row(c, Method::Ref, RaySet::Primary);
    const BenchRow* m = counter_row(c, Method::Masq, RaySet::Primary);
    const bool counters = r && m; // masq's own kernels ran with their counters
    std::vector<std::string> line = {c.scene, c.variant, counters ? fmt::format("{:.2f}", r->isect_calls) : "n/a",
                                     counters ? fmt::format("{:.2f}", m->isect_calls) : "n/a",
                                     counters ? fmt::format("{:.2f}x", r->isect_calls / m->isect_calls) : "n/a"};
    nlohmann::json j = {{"scene", c.scene}, {"variant", c.variant}};
    if (counters) {
      j["ref_isect_per_ray"] = r->isect_calls;
      j["masq_isect_per_ray"] = m->isect_calls;
      j["rt_model_speedup"] = rt_predicted_speedup(*r, *m, ctx.rt_model);
    }
    bool driver_rows = false; // a run of the driver-traversal backends alone still fills their columns
    for (const std::string& b : driver)
      for (Method method : {Method::Ref, Method::Masq}) {
        const BenchRow* d = find_row(c.rows, b, method, RaySet::Primary);
        driver_rows = driver_rows || d;
        line.push_back(d ? fmt::format("{:.2f}", d->isect_calls) : "n/a");
        j[b + "_" + method_name(method) + "_isect_per_ray"] = d ? d->isect_calls : -1.0;
      }
    if (!counters && !driver_rows) continue;
    line.push_back(counters ? rt_split(*r, ctx.rt_model) : "n/a");
    line.push_back(counters ? rt_split(*m, ctx.rt_model) : "n/a");
    line.push_back(counters ? rt_speedup_label(rt_predicted_speedup(*r, *m, ctx.rt_model), ctx.rt_model) : "n/a");
    t.add(line);
    res.data.push_back(j);
  }
  t.notes = {"primary rays; calls include the triangles of scenes that have them; rayquery: candidates the driver's BVH "
             "hands to the intersector; rtpipeline: the driver's intersection- and any-hit-shader invocations",
             "RT cost hw+sw: per ray, in intersector calls, the RT model's price of everything but the calls (fixed "
             "cost, node visits, transforms) + of the calls",
             rt_model_note(ctx.rt_model)};
  res.tables.push_back(t);
  res.method = "Counters of the stats kernel variant on the primary rays of table1's scenes.";
  if (!ctx.config.out_dir.empty() && !ctx.hair.empty()) {
    try {
      HairScene bear = hair_scenes(true).front();
      Scene s = make_case(ctx.config, bear, {"capsule", PrimType::Capsule, 1});
      res.images.push_back(write_call_heatmaps(ctx, s, "heatmap_bear.png",
                                               "Intersector calls per pixel, ref (left) vs masq (right), bear fur capsules",
                                               400, 300));
    } catch (const std::exception& e) {
      ctx.say(std::string("fig10 heatmap skipped: ") + e.what());
    }
  }
  return res;
}

} // namespace masq
