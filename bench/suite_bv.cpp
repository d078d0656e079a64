// bv: every bounding-volume idea for thin primitives on the same rays and devices, laid
// out like Kallberg & Larsson's Table 1: per scene, the trace time t, the ray/volume
// (N_b) and ray/primitive (N_t) tests per primary ray on every backend, and the bytes.
// Their binary hierarchies of slab cut balls (p = 0 and p = 0.2), balls, OBBs and AABBs
// share one topology (the paper's OBB-area SAH sweep), an AABB tree from the project's
// binned SAH is the conventional baseline, and masq's own two-level structures stand
// beside them: AABB and oriented 4-wide nodes (ref), per-primitive OBBs (masq) and
// per-cluster OBBs (cluster).
#include "bench/paper_tables.h"
#include "bench/suite.h"
#include "host/bv_tracer.h"
#include "scenes/camera.h"
#include "scenes/generators.h"
#include "scenes/loaders/load_any.h"
#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fmt/format.h>
#include <map>
#include <memory>

namespace masq {

namespace {

struct BvScenario {
  std::string label; // "Rings (SPD rings sf7)"
  std::string file;  // relative to the data dir
  std::string paper; // the scene of Kallberg & Larsson's Table 1 it stands for ("": none)
};

struct BvVariant {
  std::string label;
  BvType type;
  double p;
  BvBuilder builder;
};

const std::vector<BvVariant>& bv_variants() {
  static const std::vector<BvVariant> v = {{"SCB p=0", BvType::Scb, 0.0, BvBuilder::ObbSweep},
                                           {"SCB p=0.2", BvType::Scb, 0.2, BvBuilder::ObbSweep},
                                           {"ball", BvType::Sphere, 0.0, BvBuilder::ObbSweep},
                                           {"OBB", BvType::Obb, 0.0, BvBuilder::ObbSweep},
                                           {"AABB", BvType::Aabb, 0.0, BvBuilder::ObbSweep},
                                           {"AABB (binned SAH)", BvType::Aabb, 0.0, BvBuilder::BinnedSah}};
  return v;
}

// file "": the embedded default scene (the masquerade paper's bundle).
std::vector<BvScenario> bv_scenarios(bool quick) {
  std::vector<BvScenario> s = {{"Rings (SPD rings sf7)", "spd/rings_sf7.nff", "Rings"},
                               {"Bunny (Stanford, 69K triangles)", "meshes/bun_zipper.ply", "Bunny"},
                               {"Tree (SPD tree sf11)", "spd/tree_sf11.nff", "Tree"},
                               {"Hair (TressFX 3 TestHair1)", "hair/tressfx3_TestHair1.tfx"},
                               {"Neuron (C040600B3, round cones)", "neurons/C040600B3.CNG.swc"},
                               {"bear fur (TressFX 3)", "hair/tressfx3_bear.tfx"},
                               {"Ratboy mohawk (TressFX 4)", "hair/tressfx4_Ratboy_mohawk.tfx"},
                               {"default bundle (N=1000 r=0.002 tilt 45 + ground)", ""}};
  if (quick) s = {s[0], s[4], s[7]};
  return s;
}

// masq's two-level structures on the same rays: a method on one node format.
struct TwoLevelVariant {
  std::string label;
  Method method;
  NodeFormat nodes;
};
const std::vector<TwoLevelVariant>& two_level_variants() {
  static const std::vector<TwoLevelVariant> v = {{"AABB 4-wide (ref)", Method::Ref, NodeFormat::W4},
                                                 {"oriented 4-wide (ref o4)", Method::Ref, NodeFormat::O4},
                                                 {"OBB per primitive (masq)", Method::Masq, NodeFormat::W4},
                                                 {"OBB per cluster (cluster)", Method::Cluster, NodeFormat::W4}};
  return v;
}

struct BvCell {
  bool ok = false;
  std::string why;
  double nb = 0, nt = 0;          // per ray (cpu counters)
  double build_s = 0;             // topology + fit
  std::size_t nodes = 0;
  int depth = 0;
  std::size_t bytes = 0;          // nodes and leaf entries (two-level: nodes, refs, instances, frames)
  std::map<std::string, double> seconds; // median trace time per backend
};

// "8,400 primitives (3,000 spheres, 5,400 round cones)": the size the agreement
// sentence sets beside the paper's triangle count.
std::string scene_size(const Scene& scene) {
  std::map<std::string, std::size_t> per_type;
  for (const Geometry& g : scene.geometries) per_type[prim_type_name(g.type)] += g.primitive_count();
  std::string parts;
  for (const auto& [name, n] : per_type) parts += fmt::format("{}{} {}s", parts.empty() ? "" : ", ", n, name);
  return fmt::format("{} primitives ({})", scene.primitive_count(), parts);
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0.0 : v[v.size() / 2];
}

// A two-level structure of masq on the same rays. A wide visit tests up to 4 child
// boxes in one step and a masquerade unit box is one box test, so N_b is counted as
// 4 x (TLAS and BLAS visits): an upper bound on box tests (empty slots are skipped).
BvCell measure_two_level(SuiteContext& ctx, const Scene& scene, const TwoLevelVariant& v,
                         const std::vector<std::string>& backends, int side, int reps) {
  BvCell cell;
  BenchOptions bo = ctx.bench_options(side, side);
  bo.methods = {v.method};
  bo.node_formats = {v.nodes};
  bo.ray_sets = {RaySet::Primary};
  bo.backends = backends;
  bo.repetitions = reps;
  bo.progress = [&](const std::string& line) { ctx.say("bv: " + scene.name + " / " + v.label + ": " + line); };
  try {
    for (const BenchRow& r : run_bench(scene, bo, ctx.pool)) {
      if (!r.unavailable.empty()) continue;
      if (r.backend == "cpu" && r.tlas_nodes >= 0) {
        cell.nb = 4.0 * (r.tlas_nodes + r.blas_nodes);
        cell.nt = r.isect_calls;
      }
      cell.seconds[r.backend] = r.median_s;
      cell.build_s = r.build_s;
      cell.nodes = r.build.tlas_nodes + r.build.blas_nodes;
      cell.depth = r.build.max_depth;
      cell.bytes = r.accel_bytes;
      cell.ok = true;
    }
    if (!cell.ok) cell.why = "no backend ran";
  } catch (const std::exception& e) {
    cell.why = e.what();
  }
  return cell;
}

} // namespace

SuiteResult run_bv_suite(SuiteContext& ctx) {
  auto t0 = std::chrono::steady_clock::now();
  const bool quick = ctx.config.quick;
  const int side = quick ? 64 : 256;
  const int reps = quick ? 2 : 5;
  SuiteResult res;
  res.name = "bv";
  res.title = "Every bounding volume on the same rays: slab cut balls, balls, OBBs and AABBs (Kallberg & Larsson, "
              "Table 1 layout) beside masq's AABB and oriented wide nodes, per-primitive and per-cluster OBBs";
  // Tracers opened once for the whole suite (their kernels compile on first use).
  std::vector<std::string> backends;
  std::map<std::string, std::unique_ptr<BvTracer>> tracers;
  std::map<std::string, std::string> unavailable;
  for (const std::string& b : ctx.config.backends) {
    if (std::find(bv_backend_names().begin(), bv_backend_names().end(), b) == bv_backend_names().end()) continue;
    backends.push_back(b);
    try {
      tracers[b] = make_bv_tracer(b);
    } catch (const std::exception& e) {
      unavailable[b] = e.what();
    }
  }
  std::vector<BvScenario> scenarios = bv_scenarios(quick);
  std::vector<std::vector<BvCell>> cells(scenarios.size(), std::vector<BvCell>(bv_variants().size()));
  std::vector<std::size_t> prim_counts(scenarios.size(), 0);
  std::vector<std::string> sizes(scenarios.size());
  // masq's own two-level structures (columns after the binary trees').
  std::vector<std::vector<BvCell>> two_level(scenarios.size(), std::vector<BvCell>(two_level_variants().size()));
  res.data["scenes"] = nlohmann::json::array();
  for (std::size_t si = 0; si < scenarios.size(); ++si) {
    const BvScenario& sc = scenarios[si];
    std::string path = (std::filesystem::path(ctx.config.data_dir) / sc.file).string();
    nlohmann::json js = {{"scene", sc.label}, {"file", sc.file}};
    Scene scene;
    try {
      scene = sc.file.empty() ? make_default_scene() : load_scene_file(path);
    } catch (const std::exception& e) {
      for (BvCell& c : cells[si]) c.why = e.what();
      ctx.say("bv: " + sc.label + ": " + e.what());
      js["error"] = e.what();
      res.data["scenes"].push_back(js);
      continue;
    }
    prim_counts[si] = scene.primitive_count();
    sizes[si] = scene_size(scene);
    std::vector<kernel::Ray> rays = make_camera_rays(scene.camera, side, side);
    std::map<BvBuilder, BvTopologyPtr> topo;
    for (std::size_t vi = 0; vi < bv_variants().size(); ++vi) {
      const BvVariant& v = bv_variants()[vi];
      BvCell& cell = cells[si][vi];
      ctx.say(fmt::format("bv: {} / {}", sc.label, v.label));
      BvOptions opt;
      opt.type = v.type;
      opt.scb_p = v.p;
      opt.builder = v.builder;
      try {
        double topo_s = 0;
        if (!topo.count(v.builder)) topo[v.builder] = build_bv_topology(scene, opt);
        topo_s = bv_topology_seconds(*topo[v.builder]);
        BvScene bs = fit_bv_scene(*topo[v.builder], opt);
        cell.build_s = topo_s + bs.stats.build_seconds;
        cell.nodes = bs.stats.nodes;
        cell.depth = bs.stats.depth;
        cell.bytes = bs.node_bytes() + bs.bv_prims.size() * sizeof(kernel::BvPrimRef);
        std::vector<kernel::Hit> hits(rays.size());
        std::vector<kernel::RayStats> stats(rays.size());
        for (const std::string& b : backends) {
          if (!tracers.count(b)) continue;
          BvTracer& tr = *tracers[b];
          tr.set_scene(bs);
          if (b == "cpu") { // counters: the same on every backend (one kernel source)
            tr.trace(rays, hits, stats);
            double nb = 0, nt = 0;
            for (const kernel::RayStats& s : stats) nb += s.blas_nodes, nt += s.isect_calls;
            cell.nb = nb / double(rays.size());
            cell.nt = nt / double(rays.size());
          }
          tr.trace(rays, hits, {}); // warm-up (and first-use compile)
          std::vector<double> times;
          for (int r = 0; r < reps; ++r) {
            tr.trace(rays, hits, {});
            times.push_back(tr.timing().trace_seconds);
          }
          cell.seconds[b] = median(times);
        }
        cell.ok = true;
      } catch (const std::exception& e) {
        cell.why = e.what();
        ctx.say("bv: " + sc.label + " / " + v.label + ": " + e.what());
      }
      nlohmann::json jc = {{"variant", v.label}, {"type", bv_type_name(v.type)}, {"p", v.p},
                           {"builder", bv_builder_name(v.builder)}, {"ok", cell.ok}};
      if (cell.ok) {
        jc["n_b"] = cell.nb;
        jc["n_t"] = cell.nt;
        jc["build_seconds"] = cell.build_s;
        jc["nodes"] = cell.nodes;
        jc["depth"] = cell.depth;
        jc["bytes"] = cell.bytes;
        jc["trace_seconds"] = cell.seconds;
      } else {
        jc["error"] = cell.why;
      }
      js["variants"].push_back(jc);
    }
    for (std::size_t ti = 0; ti < two_level_variants().size(); ++ti) {
      const TwoLevelVariant& v = two_level_variants()[ti];
      const BvCell& c = two_level[si][ti] = measure_two_level(ctx, scene, v, backends, side, reps);
      js["variants"].push_back(c.ok ? nlohmann::json{{"variant", v.label}, {"ok", true}, {"n_b", c.nb}, {"n_t", c.nt},
                                                     {"build_seconds", c.build_s}, {"nodes", c.nodes},
                                                     {"bytes", c.bytes}, {"trace_seconds", c.seconds}}
                                    : nlohmann::json{{"variant", v.label}, {"ok", false}, {"error", c.why}});
    }
    js["primitives"] = prim_counts[si];
    js["rays"] = rays.size();
    res.data["scenes"].push_back(js);
  }

  // Table 1 layout: one row per scene (and backend for t), per volume type t, N_b, N_t.
  Table counts;
  counts.title = fmt::format("N_b (ray/volume tests) and N_t (ray/primitive tests) per primary ray, {}x{} rays", side, side);
  counts.header = {"scene", "prims"};
  for (const BvVariant& v : bv_variants()) {
    counts.header.push_back(v.label + " N_b");
    counts.header.push_back(v.label + " N_t");
  }
  for (const TwoLevelVariant& v : two_level_variants()) {
    counts.header.push_back(v.label + " N_b");
    counts.header.push_back(v.label + " N_t");
  }
  Table times;
  times.title = fmt::format("t: median trace time (ms) of {}x{} primary rays, median of {}", side, side, reps);
  times.header = {"scene", "backend"};
  for (const BvVariant& v : bv_variants()) times.header.push_back(v.label);
  for (const TwoLevelVariant& v : two_level_variants()) times.header.push_back(v.label);
  times.left_columns = 2;
  // The paper's own rows under masq's scene that stands for theirs, and a sentence per
  // scene on how far the two order the volume types alike. t: the cpu backend's (the
  // paper's is a single-threaded CPU tracer) or the first that ran.
  const std::string time_backend =
      std::find(backends.begin(), backends.end(), "cpu") != backends.end() ? "cpu" : backends.empty() ? "" : backends[0];
  std::vector<std::string> agreement;
  for (std::size_t si = 0; si < scenarios.size(); ++si) {
    std::vector<std::string> row = {scenarios[si].label, std::to_string(prim_counts[si])};
    std::vector<BvCell> row_cells = cells[si];
    row_cells.insert(row_cells.end(), two_level[si].begin(), two_level[si].end());
    for (const BvCell& c : row_cells) {
      row.push_back(c.ok ? fmt::format("{:.1f}", c.nb) : "n/a");
      row.push_back(c.ok ? fmt::format("{:.2f}", c.nt) : "n/a");
    }
    counts.add(row);
    for (const std::string& b : backends) {
      std::vector<std::string> trow = {scenarios[si].label, b};
      for (const BvCell& c : row_cells) {
        auto it = c.seconds.find(b);
        trow.push_back(c.ok && it != c.seconds.end() ? fmt::format("{:.2f}", it->second * 1e3) : "n/a");
      }
      times.add(trow);
    }
    const PaperBvScene* paper = paper_bv_scene(scenarios[si].paper);
    if (!paper) continue;
    std::vector<BvMeasured> measured;
    for (std::size_t vi = 0; vi < row_cells.size(); ++vi) {
      const BvCell& c = row_cells[vi];
      auto it = c.seconds.find(time_backend);
      measured.push_back({vi < bv_variants().size() ? bv_variants()[vi].label
                                                    : two_level_variants()[vi - bv_variants().size()].label,
                          c.ok && it != c.seconds.end(),
                          c.nb, c.nt, it != c.seconds.end() ? it->second : 0.0});
    }
    std::vector<std::string> prow = {fmt::format("paper: {} (M per image)", paper->name),
                                     fmt::format("{}K tris", paper->kilo_triangles)};
    for (const std::string& cell : bv_paper_counts_row(*paper, measured)) prow.push_back(cell);
    counts.add(prow);
    std::vector<std::string> ptrow = {fmt::format("paper: {}", paper->name), "T9400, 1 thread"};
    for (const std::string& cell : bv_paper_times_row(*paper, measured)) ptrow.push_back(cell);
    times.add(ptrow);
    agreement.push_back(bv_agreement(*paper, scenarios[si].label, sizes[si], time_backend, measured));
  }
  counts.notes = {"counters from the cpu backend's stats variant; the vulkan and opencl kernels are the same source",
                  "N_b counts the root test plus both children's tests at every visited inner node (the paper's N_b)",
                  "masq's two-level structures on the same rays: ref's 4-wide BVH with AABB nodes (w4) and with "
                  "oriented nodes (o4: a rotation per node where the SAH gains, docs/kernels.md), masq's OBB per "
                  "primitive (TLAS of masquerade instances) and cluster's OBB per cluster; N_b = 4 x (TLAS + BLAS "
                  "wide-node visits and masquerade unit-box tests): each visit tests up to 4 child boxes at once",
                  "paper: Kallberg & Larsson 2009, Table 1, under the masq scene that stands for theirs: N_b and N_t "
                  "in millions per image (its image size is not stated: compare orders and ratios, not values), t in s "
                  "on one core of a Core 2 Duo T9400; their scenes are triangle meshes, masq's SPD scenes are the same "
                  "generators at smaller sizes with analytic spheres, cylinders and cones (sizes below)"};
  for (auto& [b, why] : unavailable) times.notes.push_back(b + ": " + why);
  Table builds;
  builds.title = "build: seconds (topology + fit), nodes, depth";
  builds.header = {"scene"};
  for (const BvVariant& v : bv_variants()) builds.header.push_back(v.label);
  for (const TwoLevelVariant& v : two_level_variants()) builds.header.push_back(v.label);
  Table bytes;
  bytes.title = "bytes of the structure (MiB) and per primitive";
  bytes.header = builds.header;
  for (std::size_t si = 0; si < scenarios.size(); ++si) {
    std::vector<std::string> row = {scenarios[si].label}, brow = {scenarios[si].label};
    std::vector<BvCell> row_cells = cells[si];
    row_cells.insert(row_cells.end(), two_level[si].begin(), two_level[si].end());
    for (const BvCell& c : row_cells) {
      row.push_back(c.ok ? fmt::format("{:.2f}s {} d{}", c.build_s, c.nodes, c.depth) : "n/a");
      brow.push_back(c.ok ? fmt::format("{:.2f} ({:.0f} B)", double(c.bytes) / (1 << 20),
                                        double(c.bytes) / double(std::max<std::size_t>(prim_counts[si], 1)))
                          : "n/a");
    }
    builds.add(row);
    bytes.add(brow);
  }
  builds.notes = {"two-level structures: host build and upload of the first backend; nodes: TLAS + BLAS wide nodes; "
                  "d: wide levels, TLAS + BLAS"};
  bytes.notes = {"binary trees: their nodes and leaf entries; two-level structures: nodes, leaf references, instances, "
                 "compact masquerade entries and frames (the primitives, the same for all, not counted)"};
  Table agree;
  agree.title = "ordering of the volume types: Kallberg & Larsson's Table 1 vs masq (per scene both have)";
  agree.header = {"agreement"};
  for (const std::string& a : agreement) agree.add({a});
  agree.notes = {"best first, '~': within 5% of the one before (a tie); the paper's five types only (the binned-SAH "
                 "and 4-wide AABB trees are masq's); pairs ordered alike: of the 10 pairs of types, those both order "
                 "the same way or either ties; t is noise-dominated in quick runs (few rays, 2 traces)",
                 "why they may differ: the paper built each tree with its own SAH down to one primitive a leaf; masq's "
                 "five trees share one topology with up to 4 primitives a leaf, so they differ in fit alone and N_t "
                 "spreads less between types. The paper traced triangle meshes; masq's Rings and Tree are the SPD "
                 "generators' analytic spheres and round cones at a smaller size (its Bunny is the same mesh), whose "
                 "intersector costs more than a volume test. t weighs masq's own test costs (fp32, rounded outward) on "
                 "a multi-threaded tracer against a 2008 single-threaded one"};
  res.data["paper_agreement"] = agreement;
  res.tables = {counts, times, builds, bytes};
  if (!agreement.empty()) res.tables.push_back(agree);
  res.method = fmt::format(
      "Each scene loaded from the data directory and framed by its loader; {}x{} primary camera rays; one binary "
      "hierarchy over the world-space primitives per volume type (robust intersectors at the leaves), fitted in "
      "double and rounded outward to fp32; SCB slab chosen among the node OBB's three slabs by reduced area with "
      "weight p; the first five columns share the OBB-area SAH sweep topology (max leaf size 4), the sixth uses the "
      "binned SAH over AABBs; the last four are masq's two-level structures (ref w4, ref o4, masq, cluster) from "
      "the default builder. Time: device time (vulkan timestamps, OpenCL events) or wall time (cpu), median of {} "
      "traces after one warm-up.",
      side, side, reps);
  res.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return res;
}

} // namespace masq
