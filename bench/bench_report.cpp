#include "bench/bench_report.h"
#include "host/backend.h"
#include <algorithm>
#include <fmt/format.h>

namespace masq {

namespace {
std::string per_ray(double v) { return v < 0 ? "n/a" : fmt::format("{:.2f}", v); }
bool has_counters(const BenchRow& r) { return r.tlas_nodes >= 0 && r.blas_nodes >= 0 && r.transforms >= 0; }
// "shadow (any)" when the set was traced as an occlusion query.
std::string rays_label(const BenchRow& r) {
  return std::string(ray_set_name(r.ray_set)) + (r.query == Query::Any ? " (any)" : "");
}
} // namespace

const BenchRow* find_row(const std::vector<BenchRow>& rows, const std::string& backend, Method m, RaySet set) {
  for (const BenchRow& r : rows)
    if (r.backend == backend && r.method == m && r.ray_set == set && r.unavailable.empty()) return &r;
  return nullptr;
}

const BenchRow* find_row(const std::vector<BenchRow>& rows, const std::string& backend, Method m, RaySet set, Builder b) {
  for (const BenchRow& r : rows)
    if (r.backend == backend && r.method == m && r.ray_set == set && r.builder == b && r.unavailable.empty()) return &r;
  return nullptr;
}

const BenchRow* find_row(const std::vector<BenchRow>& rows, const std::string& backend, Method m, RaySet set, Builder b,
                         NodeFormat nodes, CurveIsect isect) {
  for (const BenchRow& r : rows)
    if (r.backend == backend && r.method == m && r.ray_set == set && r.builder == b && r.nodes == nodes &&
        r.curve_isect == isect && r.unavailable.empty())
      return &r;
  return nullptr;
}

std::string method_label(const BenchRow& r) {
  std::string s = method_name(r.method);
  if (r.builder != Builder::Sah) s += fmt::format(" [{}]", builder_name(r.builder));
  if (r.curve_isect != CurveIsect::Phantom) s += fmt::format(" ({})", curve_isect_name(r.curve_isect));
  if (r.query == Query::Any && r.blas_occlusion != BlasOcclusion::Nearest) s += std::string(" ") + blas_occlusion_name(r.blas_occlusion);
  return s;
}

Table bench_curve_isect_ratios(const std::vector<BenchRow>& rows) {
  Table t;
  t.header = {"backend", "method", "nodes", "rays", "curve isect", "Mrays/s", "speed vs phantom", "isect/r", "hit%"};
  t.left_columns = 5;
  for (const BenchRow& r : rows) {
    if (!r.unavailable.empty()) continue;
    const BenchRow* p = find_row(rows, r.backend, r.method, r.ray_set, r.builder, r.nodes, CurveIsect::Phantom);
    t.add({r.backend, method_label(r), node_format_name(r.nodes), rays_label(r), curve_isect_name(r.curve_isect),
           fmt::format("{:.3f}", r.mrays_per_s()), p ? fmt::format("{:.2f}x", r.mrays_per_s() / p->mrays_per_s()) : "-",
           r.isect_calls >= 0 ? fmt::format("{:.2f}", r.isect_calls) : "n/a", fmt::format("{:.1f}", 100.0 * r.hit_fraction)});
  }
  t.notes = {"speed vs phantom: Mrays/s of this row over the phantom row of the same backend, method, builder, node "
             "format and rays (one run, same rays, the rows taking turns round by round)"};
  return t;
}

namespace {
double refs_per_prim(const BuildStats& b) {
  return b.blas_primitives ? double(b.blas_references) / double(b.blas_primitives) : 1.0;
}
} // namespace

Table bench_builders(const std::vector<BenchRow>& rows) {
  Table t;
  std::vector<Builder> seen;
  for (const BenchRow& r : rows)
    if (std::find(seen.begin(), seen.end(), r.builder) == seen.end()) seen.push_back(r.builder);
  if (seen.size() < 2) return t;
  // The first builder of the run is the base (rows are ordered by builder within a method).
  Builder base = seen.front();
  for (const BenchRow& r : rows)
    if (r.unavailable.empty()) {
      base = r.builder;
      break;
    }
  t.header = {"backend", "method", "rays", "builder", "nodes", "TLAS SAH", "BLAS SAH", "refs/prim", "build ms", "nodes/r", "isect/r",
              "Mrays/s", fmt::format("speed / {}", builder_name(base)), "nodes/r ratio", "isect/r ratio", "SAH ratio",
              "build ratio"};
  t.left_columns = 5;
  for (const BenchRow& r : rows) {
    if (!r.unavailable.empty()) continue;
    const BenchRow* b = find_row(rows, r.backend, r.method, r.ray_set, base, r.nodes, r.curve_isect);
    auto ratio = [&](double x, double y) { return b && y > 0 && x >= 0 ? fmt::format("{:.3f}", x / y) : std::string("-"); };
    // Wide-node visits per ray, TLAS and BLAS (-1 where the backend cannot count them).
    auto nodes = [](const BenchRow& x) { return x.tlas_nodes < 0 || x.blas_nodes < 0 ? -1.0 : x.tlas_nodes + x.blas_nodes; };
    double sah = r.build.sah_cost + r.build.blas_sah_cost;
    double base_sah = b ? b->build.sah_cost + b->build.blas_sah_cost : 0.0;
    t.add({r.backend, method_name(r.method), rays_label(r), builder_name(r.builder), node_format_name(r.nodes),
           fmt::format("{:.2f}", r.build.sah_cost),
           fmt::format("{:.2f}", r.build.blas_sah_cost), fmt::format("{:.3f}", refs_per_prim(r.build)),
           fmt::format("{:.1f}", r.build.build_seconds * 1e3), per_ray(nodes(r)), per_ray(r.isect_calls),
           fmt::format("{:.3f}", r.mrays_per_s()), ratio(r.mrays_per_s(), b ? b->mrays_per_s() : 0.0),
           ratio(nodes(r), b ? nodes(*b) : 0.0), ratio(r.isect_calls, b ? b->isect_calls : 0.0),
           ratio(sah, base_sah), ratio(r.build.build_seconds, b ? b->build.build_seconds : 0.0)});
  }
  t.notes = {"SAH: the wide BVH's cost (1 per node visit, 1 per reference, relative to the root area; BLAS summed over "
             "every BLAS, each relative to its own root); refs/prim: BLAS leaf references per primitive (> 1: spatial "
             "splits); build ms: host build of the whole two-level structure; nodes/r: wide-node visits per ray (TLAS + BLAS)",
             fmt::format("ratios: this builder over {} for the same backend, method, node format and rays (SAH ratio: TLAS + BLAS "
                         "cost); the machine is shared and noisy, so speed ratios within ~5% are noise",
                         builder_name(base))};
  return t;
}

Table bench_node_ratios(const std::vector<BenchRow>& rows) {
  Table t;
  t.header = {"backend", "method", "nodes", "rays", "speed vs w4", "node visits/r", "vs w4", "node MiB", "vs w4",
              "node B/prim"};
  t.left_columns = 4;
  for (const BenchRow& r : rows) {
    if (!r.unavailable.empty()) continue;
    const BenchRow* w4 = find_row(rows, r.backend, r.method, r.ray_set, r.builder, NodeFormat::W4, r.curve_isect);
    double visits = r.tlas_nodes + r.blas_nodes;
    bool counted = r.tlas_nodes >= 0 && r.blas_nodes >= 0;
    double w4_visits = w4 ? w4->tlas_nodes + w4->blas_nodes : 0;
    t.add({r.backend, method_label(r), node_format_name(r.nodes), rays_label(r),
           w4 ? fmt::format("{:.2f}x", r.mrays_per_s() / w4->mrays_per_s()) : "-",
           counted ? fmt::format("{:.2f}", visits) : "n/a",
           counted && w4 && w4_visits > 0 ? fmt::format("{:.2f}x", visits / w4_visits) : "-",
           fmt::format("{:.3f}", r.build.node_bytes / 1048576.0),
           w4 && w4->build.node_bytes > 0 ? fmt::format("{:.2f}x", double(r.build.node_bytes) / double(w4->build.node_bytes))
                                          : "-",
           fmt::format("{:.1f}", double(r.build.node_bytes) / double(std::max<std::size_t>(1, r.primitives)))});
  }
  t.notes = {"node visits/r: TLAS + BLAS node visits per ray (masquerade unit-box tests included, as in blas/r); "
             "node MiB / B/prim: the TLAS and BLAS nodes alone, in the row's format (refs, instances, compact entries and frames "
             "are the same for every format)",
             "speed vs w4: Mrays/s of this row over the w4 row of the same backend, method and rays (one run, "
             "same rays)"};
  return t;
}

Table bench_table(const std::vector<BenchRow>& rows) {
  Table t;
  t.header = {"backend", "method",  "nodes",   "rays",      "Mrays/s", "(min-max)", "dev ms",   "wall ms",
              "up/back ms", "tlas/r", "blas/r", "xf/r", "isect/r", "hit%", "accel MiB", "B/prim", "dev MiB", "build ms",
              "compile ms"};
  t.left_columns = 4;
  std::vector<std::string> why; // one note per distinct reason, so the columns stay narrow
  std::vector<std::string> unfilled; // one note per device and ray count too small to fill it
  for (const BenchRow& r : rows) {
    if (r.unavailable.empty() && r.fill_rays > 0 && r.rays < double(r.fill_rays)) {
      std::string note = fmt::format("too small to fill the device: {} on {} traces {:.0f} rays at a time; it needs "
                                     "about {} to keep every lane busy (host/device_fill.h); raise --width/--height",
                                     r.backend, r.device, r.rays, r.fill_rays);
      if (std::find(unfilled.begin(), unfilled.end(), note) == unfilled.end()) unfilled.push_back(note);
    }
    if (!r.unavailable.empty()) {
      auto it = std::find(why.begin(), why.end(), r.unavailable);
      std::size_t k = std::size_t(it - why.begin()) + 1;
      if (it == why.end()) why.push_back(r.unavailable);
      t.add({r.backend, method_label(r), node_format_name(r.nodes), rays_label(r),
             fmt::format("unavailable [{}]", k)});
      continue;
    }
    t.add({r.backend, method_label(r), node_format_name(r.nodes), rays_label(r), fmt::format("{:.3f}", r.mrays_per_s()),
           fmt::format("({:.3f}-{:.3f})", r.rays / r.max_s * 1e-6, r.rays / r.min_s * 1e-6),
           fmt::format("{:.2f}", r.median_s * 1e3), fmt::format("{:.2f}", r.wall_s * 1e3),
           fmt::format("{:.2f}/{:.2f}", r.upload_s * 1e3, r.readback_s * 1e3), per_ray(r.tlas_nodes),
           per_ray(r.blas_nodes), per_ray(r.transforms), per_ray(r.isect_calls), fmt::format("{:.1f}", 100.0 * r.hit_fraction),
           fmt::format("{:.3f}", r.accel_bytes / 1048576.0),
           fmt::format("{:.1f}", double(r.accel_bytes) / double(std::max<std::size_t>(1, r.primitives))),
           fmt::format("{:.3f}", r.device_bytes / 1048576.0), fmt::format("{:.1f}", (r.build_s + r.scene_s) * 1e3),
           fmt::format("{:.1f}", r.compile_s * 1e3)});
  }
  t.notes = {"Mrays/s and dev ms: device time of one trace (median; Vulkan timestamps, OpenCL events, cpu wall); wall "
             "ms: the same trace on the host clock (uploads, dispatches, waits, readbacks); up/back ms: its ray upload "
             "and hit/counter readback (cpu: 0, it traces in place)",
             "per ray: tlas/blas = wide-node visits, xf = instance transforms, isect = intersector calls (rayquery, rtpipeline: the "
             "driver's traversal is not observable, n/a); hit% for shadow rays is the occluded fraction",
             "accel MiB / B/prim: masq's own two-level BVH (nodes, refs, instances, compact masquerade entries and "
             "their owners, frames); dev MiB: what the backend "
             "holds on the device (rayquery, rtpipeline: the driver's acceleration structures, BLAS compacted, plus primitives); build "
             "ms: host build + upload/driver build; compile ms: the variant's kernel/pipeline compile on its first use (Vulkan "
             "backends: once per device), shown in every row that runs it (cpu: 0, compiled in)"};
  for (const std::string& n : unfilled) t.notes.push_back(n);
  for (std::size_t k = 0; k < why.size(); ++k) t.notes.push_back(fmt::format("[{}] {}", k + 1, why[k]));
  // Each row's device, once per backend (docs/devices.md: the chosen device, never assumed).
  std::string devices;
  std::vector<std::string> named;
  for (const BenchRow& r : rows) {
    if (!r.unavailable.empty() || r.device.empty() || std::find(named.begin(), named.end(), r.backend) != named.end())
      continue;
    named.push_back(r.backend);
    devices += fmt::format("{}{} on {}", devices.empty() ? "devices: " : "; ", r.backend, r.device);
  }
  if (!devices.empty()) t.notes.push_back(devices);
  return t;
}

Table bench_ratios(const std::vector<BenchRow>& rows, const RtCostModel& model) {
  Table t;
  t.header = {"backend", "method", "nodes", "rays", "speedup", "vs masq", "isect calls ref/this", "accel memory this/ref",
              "OBB/AABB area", "RT model speedup"};
  t.left_columns = 4;
  for (const BenchRow& m : rows) {
    if (m.method == Method::Ref || !m.unavailable.empty()) continue;
    const BenchRow* r = find_row(rows, m.backend, Method::Ref, m.ray_set, m.builder, m.nodes, m.curve_isect);
    if (!r) continue;
    const BenchRow* q = m.method == Method::Masq ? nullptr
                                                 : find_row(rows, m.backend, Method::Masq, m.ray_set, m.builder, m.nodes, m.curve_isect);
    t.add({m.backend, method_label(m), node_format_name(m.nodes), rays_label(m),
           fmt::format("{:.2f}x", m.mrays_per_s() / r->mrays_per_s()),
           q ? fmt::format("{:.2f}x", m.mrays_per_s() / q->mrays_per_s()) : "-",
           fmt::format("{:.2f}x ({:.2f} vs {:.2f})", r->isect_calls / m.isect_calls, r->isect_calls, m.isect_calls),
           fmt::format("{:.2f}x", double(m.accel_bytes) / double(r->accel_bytes)),
           m.build.aabb_area > 0 ? fmt::format("{:.3f}", m.build.obb_area / m.build.aabb_area) : "-",
           has_counters(m) && has_counters(*r) ? rt_speedup_label(rt_predicted_speedup(*r, m, model), model) : "n/a"});
  }
  t.notes = {rt_model_note(model)};
  return t;
}

Table bench_headline(const std::vector<BenchRow>& rows) {
  Table t;
  t.header = {"backend", "rays", "ref Mrays/s", "masq vs ref", "isect calls ref/masq", "fastest", "vs ref"};
  t.left_columns = 2;
  for (const BenchRow& r : rows) {
    if (r.method != Method::Ref || !r.unavailable.empty() || !(r.mrays_per_s() > 0)) continue;
    const BenchRow* m = find_row(rows, r.backend, Method::Masq, r.ray_set, r.builder, r.nodes, r.curve_isect);
    if (m && (!m->unavailable.empty() || !(m->mrays_per_s() > 0))) m = nullptr;
    const BenchRow* best = &r;
    for (const BenchRow& o : rows)
      if (o.backend == r.backend && o.ray_set == r.ray_set && o.builder == r.builder && o.nodes == r.nodes &&
          o.curve_isect == r.curve_isect && o.unavailable.empty() && o.mrays_per_s() > best->mrays_per_s())
        best = &o;
    std::string label = r.backend;
    if (r.builder != Builder::Sah) label += std::string(" ") + builder_name(r.builder);
    if (r.nodes != NodeFormat::W4) label += std::string(" ") + node_format_name(r.nodes);
    t.add({label, rays_label(r), fmt::format("{:.3f}", r.mrays_per_s()),
           m ? fmt::format("{:.2f}x", m->mrays_per_s() / r.mrays_per_s()) : "-",
           m && m->isect_calls > 0 ? fmt::format("{:.1f}x", r.isect_calls / m->isect_calls) : "-",
           method_label(*best), fmt::format("{:.2f}x", best->mrays_per_s() / r.mrays_per_s())});
  }
  t.notes = {"masq vs ref: the masquerade's rays/s over ref's; isect calls ref/masq: intersector calls it saves",
             "fastest: the quickest method of this run on that backend and ray set, against ref"};
  return t;
}

nlohmann::json bench_row_json(const BenchRow& r) {
  nlohmann::json e = {{"backend", r.backend}, {"method", method_name(r.method)}, {"builder", builder_name(r.builder)},
                      {"nodes", node_format_name(r.nodes)}, {"curve_isect", curve_isect_name(r.curve_isect)}, {"blas_occlusion", blas_occlusion_name(r.blas_occlusion)},
                      {"rays", ray_set_name(r.ray_set)}, {"query", query_name(r.query)},
                      {"device", r.device}};
  e["bytes"] = {{"acceleration", r.accel_bytes}, {"primitives", r.prim_bytes}, {"device", r.device_bytes}};
  e["primitives"] = r.primitives;
  e["kernel_stacks"] = {{"tlas", r.tlas_stack}, {"blas", r.blas_stack},
                        {"bytes_per_thread", stack_bytes(r.tlas_stack, r.blas_stack)}};
  e["build"] = {{"tlas_sah", r.build.sah_cost}, {"blas_sah", r.build.blas_sah_cost},
                {"tlas_nodes", r.build.tlas_nodes}, {"blas_nodes", r.build.blas_nodes}, {"node_bytes", r.build.node_bytes},
                {"instances", r.build.instances}, {"max_depth", r.build.max_depth},
                {"obb_area", r.build.obb_area},   {"aabb_area", r.build.aabb_area},
                {"clusters", r.build.clusters},   {"masq_prims", r.build.masq_prims},
                {"blas_references", r.build.blas_references}, {"blas_primitives", r.build.blas_primitives},
                {"seconds", r.build.build_seconds}};
  if (r.method == Method::Auto) {
    const auto& k = r.build.auto_candidates;
    e["auto"] = {{"kept", r.build.auto_choice == Method::Auto ? "mix" : method_name(r.build.auto_choice)},
                 {"model_cost", {{"ref", k[0]}, {"masq", k[1]}, {"cluster", k[2]}, {"mix", k[3]}}}};
    if (r.pilot_rays > 0) {
      const auto& p = r.pilot_seconds;
      e["auto"]["pilot"] = {{"rays", r.pilot_rays}, {"wall_seconds", r.pilot_s},
                            {"seconds", {{"ref", p[0]}, {"masq", p[1]}, {"cluster", p[2]}, {"mix", p[3]}}},
                            {"mix_is_ref", r.pilot_mix_is_ref}};
    }
  }
  if (!r.unavailable.empty()) {
    e["unavailable"] = r.unavailable;
    return e;
  }
  e["ray_count"] = r.rays;
  e["trace_seconds"] = {{"median", r.median_s}, {"min", r.min_s}, {"max", r.max_s}};
  e["wall_seconds"] = r.wall_s; // medians over the timed traces, like trace_seconds.median
  e["upload_seconds"] = r.upload_s;
  e["readback_seconds"] = r.readback_s;
  e["cpu_seconds"] = r.cpu_s; // the process's CPU time per trace, every thread (median)
  e["fill_rays"] = r.fill_rays; // 0: the device does not say
  e["mrays_per_s"] = r.mrays_per_s();
  e["per_ray"] = {{"tlas_nodes", r.tlas_nodes}, {"blas_nodes", r.blas_nodes}, {"transforms", r.transforms},
                  {"isect_calls", r.isect_calls}};
  e["hit_fraction"] = r.hit_fraction;
  e["seconds"] = {{"host_build", r.build_s}, {"upload_and_driver_build", r.scene_s}, {"compile", r.compile_s}};
  return e;
}

nlohmann::json bench_json(const Scene& scene, const BenchOptions& opt, const std::vector<BenchRow>& rows) {
  nlohmann::json j;
  j["scene"] = {{"name", scene.name}, {"primitives", scene.primitive_count()}};
  j["camera_rays"] = {{"width", opt.width}, {"height", opt.height}};
  j["warmup"] = opt.warmup;
  j["repetitions"] = opt.repetitions;
  j["auto_by"] = auto_by_name(opt.auto_by);
  j["results"] = nlohmann::json::array();
  for (const BenchRow& r : rows) j["results"].push_back(bench_row_json(r));
  return j;
}

} // namespace masq
