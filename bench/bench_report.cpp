#include "bench/bench_report.h"
#include <fmt/format.h>

namespace masq {

namespace {
std::string per_ray(double v) { return v < 0 ? "n/a" : fmt::format("{:.2f}", v); }
} // namespace

std::string bench_table(const std::vector<BenchRow>& rows) {
  std::string out = fmt::format("{:<9} {:<5} {:>9} {:>17} {:>7} {:>7} {:>7} {:>7} {:>6} {:>9} {:>7} {:>8} {:>8}\n",
                                "backend", "meth", "Mrays/s", "(min-max)", "tlas/r", "blas/r", "xf/r",
                                "isect/r", "hit%", "accel MiB", "B/prim", "dev MiB", "build ms");
  for (const BenchRow& r : rows) {
    if (!r.unavailable.empty()) {
      out += fmt::format("{:<9} {:<5} unavailable: {}\n", r.backend, method_name(r.method), r.unavailable);
      continue;
    }
    out += fmt::format("{:<9} {:<5} {:>9.3f} {:>17} {:>7} {:>7} {:>7} {:>7} {:>6.1f} {:>9.3f} {:>7.1f} {:>8.3f} {:>8.1f}\n",
                       r.backend, method_name(r.method), r.mrays_per_s(),
                       fmt::format("({:.3f}-{:.3f})", r.rays / r.max_s * 1e-6, r.rays / r.min_s * 1e-6),
                       per_ray(r.tlas_nodes), per_ray(r.blas_nodes), per_ray(r.transforms), per_ray(r.isect_calls),
                       100.0 * r.hit_fraction, r.accel_bytes / 1048576.0,
                       double(r.accel_bytes) / double(std::max<std::size_t>(1, r.primitives)),
                       r.device_bytes / 1048576.0, (r.build_s + r.scene_s) * 1e3);
  }
  return out;
}

std::string bench_ratios(const std::vector<BenchRow>& rows) {
  std::string out;
  for (const BenchRow& m : rows) {
    if (m.method != Method::Masq || !m.unavailable.empty()) continue;
    for (const BenchRow& r : rows) {
      if (r.backend != m.backend || r.method != Method::Ref || !r.unavailable.empty()) continue;
      out += fmt::format("{:<9} masq vs ref: speedup {:.2f}x, intersector calls {:.2f}x fewer ({:.2f} vs {:.2f} per ray), "
                         "acceleration memory {:.2f}x, OBB/AABB surface area {:.3f}\n",
                         m.backend, m.mrays_per_s() / r.mrays_per_s(), r.isect_calls / m.isect_calls, m.isect_calls,
                         r.isect_calls, double(m.accel_bytes) / double(r.accel_bytes),
                         m.build.aabb_area > 0 ? m.build.obb_area / m.build.aabb_area : 0.0);
    }
  }
  return out;
}

nlohmann::json bench_json(const Scene& scene, const BenchOptions& opt, const std::vector<BenchRow>& rows) {
  nlohmann::json j;
  j["scene"] = {{"name", scene.name}, {"primitives", scene.primitive_count()}};
  j["rays"] = {{"width", opt.width}, {"height", opt.height}, {"kind", "primary"}};
  j["warmup"] = opt.warmup;
  j["repetitions"] = opt.repetitions;
  for (const BenchRow& r : rows) {
    nlohmann::json e = {{"backend", r.backend}, {"method", method_name(r.method)}, {"device", r.device}};
    if (!r.unavailable.empty()) {
      e["unavailable"] = r.unavailable;
    } else {
      e["trace_seconds"] = {{"median", r.median_s}, {"min", r.min_s}, {"max", r.max_s}};
      e["mrays_per_s"] = r.mrays_per_s();
      e["per_ray"] = {{"tlas_nodes", r.tlas_nodes}, {"blas_nodes", r.blas_nodes}, {"transforms", r.transforms},
                      {"isect_calls", r.isect_calls}};
      e["hit_fraction"] = r.hit_fraction;
      e["seconds"] = {{"host_build", r.build_s}, {"upload_and_driver_build", r.scene_s}, {"compile", r.compile_s}};
      e["bytes"] = {{"acceleration", r.accel_bytes}, {"primitives", r.prim_bytes}, {"device", r.device_bytes}};
      e["build"] = {{"tlas_sah", r.build.sah_cost}, {"blas_sah", r.build.blas_sah_cost},
                    {"tlas_nodes", r.build.tlas_nodes}, {"blas_nodes", r.build.blas_nodes},
                    {"instances", r.build.instances}, {"max_depth", r.build.max_depth},
                    {"obb_area", r.build.obb_area},   {"aabb_area", r.build.aabb_area}};
    }
    j["results"].push_back(e);
  }
  return j;
}

} // namespace masq
