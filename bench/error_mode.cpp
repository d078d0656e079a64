#include "bench/error_mode.h"
#include "bvh/twolevel/build_accel.h"
#include "oracle/oracle.h"
#include "scenes/camera.h"
#include "scenes/curve_tools.h"
#include "scenes/prim_table.h"
#include "masq/error.h"
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
    if (scene_prim_row(g.type).shape == PrimShape::Bezier && !g.curves.empty()) return g.curves.front().radius;
  throw Error("bench --error: the scene has no curves (use --prim curve)");
}

// Builds the variant's scene, times it and compares every ray with the oracle.
void measure_variant(ErrorRow& row, Backend& be, const Scene& scene, const std::vector<kernel::Ray>& rays,
                     const std::vector<oracle::OracleHit>& truth, double r, const BenchOptions& opt) {
  const ErrorVariant& v = row.variant;
  Scene s = v.segments > 0 ? curves_to_segments(scene, v.segments, PrimType::Capsule)
                           : subdivide_curves(scene, v.subdivisions);
  AccelOptions ao = opt.accel;
  ao.mode = v.mode;
  ao.curve_iters = v.curve_iters;
  ao.curve_isect = v.curve_isect;
  opt.say(row.backend + " " + v.name);
  be.set_scene(build_accel(s, Method::Masq, ao));
  std::vector<kernel::Hit> hits(rays.size());
  std::vector<double> times;
  for (int i = 0; i < opt.warmup + opt.repetitions; ++i) {
    be.trace(rays, hits, {});
    if (i >= opt.warmup) times.push_back(be.timing().trace_seconds);
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
}

// Pareto front per backend in (median time, disagreement rate, mean |dt|/r).
void mark_pareto(std::vector<ErrorRow>& rows) {
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
}

} // namespace

std::vector<ErrorVariant> default_error_variants() {
  std::vector<ErrorVariant> v;
  for (Mode m : {Mode::Robust, Mode::Fast})
    for (int k : {1, 2, 4, 8}) v.push_back({fmt::format("cubic {} it24 x{}", mode_name(m), k), m, 24, k, 0});
  for (int it : {2, 4, 8, 12}) v.push_back({fmt::format("cubic robust it{} x1", it), Mode::Robust, it, 1, 0});
  for (int n : {1, 2, 4, 8, 16}) v.push_back({fmt::format("linear x{} robust", n), Mode::Robust, 24, 1, n});
  // Roving capsules (kernels/curve_roving.h) on the same cubics, in both modes.
  for (Mode m : {Mode::Robust, Mode::Fast})
    v.push_back({fmt::format("roving {} x1", mode_name(m)), m, 24, 1, 0, CurveIsect::Roving});
  return v;
}

std::vector<ErrorRow> run_error_bench(const Scene& scene, const std::vector<ErrorVariant>& variants,
                                      const BenchOptions& opt, BackendPool& pool) {
  const double r = curve_radius(scene);
  std::vector<kernel::Ray> rays = make_camera_rays(scene.camera, opt.width, opt.height);
  opt.say(fmt::format("oracle: {} rays x {} primitives (exact cubics, long double)", rays.size(),
                       scene.primitive_count()));
  std::vector<oracle::OracleHit> truth = oracle::Oracle(scene, {.exact_clearance_below = 1}).trace_all(rays);
  std::vector<ErrorRow> rows;
  for (const std::string& name : opt.backends) {
    Backend* be = pool.get(name);
    for (const ErrorVariant& v : variants) {
      ErrorRow row;
      row.backend = name;
      row.variant = v;
      row.rays = double(rays.size());
      if (!be) {
        row.unavailable = pool.why(name);
      } else {
        try {
          measure_variant(row, *be, scene, rays, truth, r, opt);
        } catch (const std::exception& e) {
          row.unavailable = e.what();
        }
      }
      rows.push_back(row);
    }
  }
  mark_pareto(rows);
  return rows;
}

Table error_table(const std::vector<ErrorRow>& rows) {
  Table t;
  t.header = {"backend", "variant", "Mrays/s", "ms median (min-max)", "disagree", "mean|dt|/r", "max|dt|/r", "pareto"};
  t.left_columns = 2;
  for (const ErrorRow& r : rows) {
    if (!r.unavailable.empty()) {
      t.add({r.backend, r.variant.name, "unavailable: " + r.unavailable});
      continue;
    }
    t.add({r.backend, r.variant.name, fmt::format("{:.3f}", r.mrays_per_s()),
           fmt::format("{:.1f} ({:.1f}-{:.1f})", r.median_s * 1e3, r.min_s * 1e3, r.max_s * 1e3), fmt::format("{:.2e}", r.rate()),
           fmt::format("{:.2e}", r.mean_dt), fmt::format("{:.2e}", r.max_dt), r.pareto ? "*" : ""});
  }
  t.notes = {"cubic <mode> it<N> x<k>: phantom curves, N iterations, each cubic pre-split into k (robust mode: the certified "
             "subdivision, which has no iteration limit); roving <mode> x1: roving capsules on the same cubics; linear xN: "
             "each curve as N capsules",
             "pareto *: no other variant on that backend is at once faster, fewer disagreements and smaller mean |dt|/r"};
  return t;
}

nlohmann::json error_json(const std::vector<ErrorRow>& rows) {
  nlohmann::json j = nlohmann::json::array();
  for (const ErrorRow& r : rows) {
    nlohmann::json e{{"backend", r.backend},       {"variant", r.variant.name},
                     {"mode", mode_name(r.variant.mode)}, {"curve_iters", r.variant.curve_iters},
                     {"subdivisions", r.variant.subdivisions}, {"segments", r.variant.segments},
                     {"curve_isect", curve_isect_name(r.variant.curve_isect)}};
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
