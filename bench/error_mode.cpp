#include "bench/error_mode.h"
#include "bvh/build_accel.h"
#include "oracle/oracle.h"
#include "scenes/camera.h"
#include "scenes/curve_tools.h"
#include "scenes/error.h"
#include <fmt/format.h>
#include <algorithm>
#include <cmath>

namespace masq {

namespace {

// Rays whose oracle clearance is below this are ambiguous in fp32 at the distances of
// the bench scenes (~1e3 radii: 4u * 1e3 is 2.4e-4) and are counted, not compared.
constexpr double kAmbiguous = 1e-3;

double curve_radius(const Scene& s) {
  for (const Geometry& g : s.geometries)
    if (g.type == PrimType::Curve && !g.curves.empty()) return g.curves.front().radius;
  throw Error("bench --error: the scene has no curves (use --prim curve)");
}

void say(const BenchOptions& opt, const std::string& line) {
  if (opt.progress) opt.progress(line);
}

} // namespace

std::vector<ErrorVariant> default_error_variants() {
  std::vector<ErrorVariant> v;
  for (Mode m : {Mode::Robust, Mode::Fast})
    for (int k : {1, 2, 4, 8}) v.push_back({fmt::format("cubic {} it24 x{}", mode_name(m), k), m, 24, k, 0});
  for (int it : {2, 4, 8, 12}) v.push_back({fmt::format("cubic robust it{} x1", it), Mode::Robust, it, 1, 0});
  for (int n : {1, 2, 4, 8, 16}) v.push_back({fmt::format("linear x{} robust", n), Mode::Robust, 24, 1, n});
  return v;
}

std::vector<ErrorRow> run_error_bench(const Scene& scene, const std::vector<ErrorVariant>& variants,
                                      const BenchOptions& opt) {
  const double r = curve_radius(scene);
  std::vector<kernel::Ray> rays = make_camera_rays(scene.camera, opt.width, opt.height);
  say(opt, fmt::format("oracle: {} rays x {} primitives (exact cubics, long double)", rays.size(),
                       scene.primitive_count()));
  std::vector<oracle::OracleHit> truth = oracle::Oracle(scene).trace_all(rays);
  std::vector<ErrorRow> rows;
  for (const std::string& name : opt.backends) {
    std::unique_ptr<Backend> be;
    std::string why;
    try {
      be = make_backend(name);
    } catch (const std::exception& e) {
      why = e.what();
    }
    for (const ErrorVariant& v : variants) {
      ErrorRow row;
      row.backend = name;
      row.variant = v;
      row.rays = double(rays.size());
      if (!be) {
        row.unavailable = why;
        rows.push_back(row);
        continue;
      }
      Scene s = v.segments > 0 ? curves_to_segments(scene, v.segments, PrimType::Capsule)
                               : subdivide_curves(scene, v.subdivisions);
      AccelOptions ao = opt.accel;
      ao.mode = v.mode;
      ao.curve_iters = v.curve_iters;
      say(opt, name + " " + v.name);
      be->set_scene(build_accel(s, Method::Masq, ao));
      std::vector<kernel::Hit> hits(rays.size());
      std::vector<double> times;
      for (int i = 0; i < opt.warmup + opt.repetitions; ++i) {
        be->trace(rays, hits, {});
        if (i >= opt.warmup) times.push_back(be->timing().trace_seconds);
      }
      std::sort(times.begin(), times.end());
      row.median_s = times[times.size() / 2];
      row.min_s = times.front();
      row.max_s = times.back();
      double sum_dt = 0, n_dt = 0;
      for (std::size_t i = 0; i < rays.size(); ++i) {
        const oracle::OracleHit& o = truth[i];
        if (double(o.clearance) < kAmbiguous) {
          row.ambiguous++;
          continue;
        }
        row.compared++;
        bool kh = hits[i].prim >= 0, oh = o.prim >= 0;
        if (kh != oh) {
          row.disagree++;
          continue;
        }
        if (!kh) continue;
        const float* d = rays[i].dir;
        double dl = std::sqrt(double(d[0]) * d[0] + double(d[1]) * d[1] + double(d[2]) * d[2]);
        double dt = std::fabs(double(hits[i].t) - double(o.t)) * dl / r;
        if (dt > 1.0) {
          row.disagree++; // a different surface
          continue;
        }
        row.max_dt = std::max(row.max_dt, dt);
        sum_dt += dt;
        n_dt += 1;
      }
      row.mean_dt = n_dt > 0 ? sum_dt / n_dt : 0;
      rows.push_back(row);
    }
  }
  // Pareto front per backend in (median time, disagreement rate, mean |dt|/r).
  for (ErrorRow& a : rows) {
    if (!a.unavailable.empty()) continue;
    a.pareto = true;
    for (const ErrorRow& b : rows) {
      if (&a == &b || b.backend != a.backend || !b.unavailable.empty()) continue;
      bool no_worse = b.median_s <= a.median_s && b.rate() <= a.rate() && b.mean_dt <= a.mean_dt;
      bool better = b.median_s < a.median_s || b.rate() < a.rate() || b.mean_dt < a.mean_dt;
      if (no_worse && better) a.pareto = false;
    }
  }
  return rows;
}

std::string error_table(const std::vector<ErrorRow>& rows) {
  std::string out = fmt::format("{:<9} {:<22} {:>8} {:>20} {:>9} {:>10} {:>10} {:>6}\n", "backend", "variant",
                                "Mrays/s", "ms median (min-max)", "disagree", "mean|dt|/r", "max|dt|/r", "pareto");
  for (const ErrorRow& r : rows) {
    if (!r.unavailable.empty()) {
      out += fmt::format("{:<9} {:<22} unavailable: {}\n", r.backend, r.variant.name, r.unavailable);
      continue;
    }
    out += fmt::format("{:<9} {:<22} {:>8.3f} {:>7.1f} ({:.1f}-{:.1f}) {:>9.2e} {:>10.2e} {:>10.2e} {:>6}\n",
                       r.backend, r.variant.name, r.mrays_per_s(), r.median_s * 1e3, r.min_s * 1e3, r.max_s * 1e3,
                       r.rate(), r.mean_dt, r.max_dt, r.pareto ? "*" : "");
  }
  return out;
}

nlohmann::json error_json(const std::vector<ErrorRow>& rows) {
  nlohmann::json j = nlohmann::json::array();
  for (const ErrorRow& r : rows) {
    nlohmann::json e{{"backend", r.backend},       {"variant", r.variant.name},
                     {"mode", mode_name(r.variant.mode)}, {"curve_iters", r.variant.curve_iters},
                     {"subdivisions", r.variant.subdivisions}, {"segments", r.variant.segments}};
    if (!r.unavailable.empty()) {
      e["unavailable"] = r.unavailable;
    } else {
      e.update({{"rays", r.rays},           {"median_s", r.median_s}, {"min_s", r.min_s},
                {"max_s", r.max_s},         {"mrays_per_s", r.mrays_per_s()}, {"compared", r.compared},
                {"ambiguous", r.ambiguous}, {"disagree", r.disagree}, {"rate", r.rate()},
                {"mean_dt_over_r", r.mean_dt}, {"max_dt_over_r", r.max_dt}, {"pareto", r.pareto}});
    }
    j.push_back(e);
  }
  return j;
}

} // namespace masq
