// `masq bench --error`: run time against error. The same rays go through every
// intersector variant of a curve scene (robust/fast, phantom iteration limits, cubic
// pre-subdivision, curves replaced by N linear capsules) on each backend; each variant
// is timed and compared with the long-double oracle of the exact cubic scene. The
// Pareto front (no other variant both faster and more accurate) is marked.
#pragma once
#include "bench/bench_runner.h"
#include "bench/table.h"
#include "scenes/scene.h"
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace masq {

struct ErrorVariant {
  std::string name;    // e.g. "cubic robust it24 x1", "linear x8"
  Mode mode = Mode::Robust;
  int curve_iters = 24;
  int subdivisions = 1; // cubic pieces per curve
  int segments = 0;     // > 0: curves replaced by this many capsules each
  CurveIsect curve_isect = CurveIsect::Phantom;
};

struct ErrorRow {
  std::string backend;
  ErrorVariant variant;
  std::string unavailable;
  double rays = 0, median_s = 0, min_s = 0, max_s = 0;
  double compared = 0, ambiguous = 0, disagree = 0;
  double max_dt = 0, mean_dt = 0; // |dt| * |d| / r over agreeing hits
  bool pareto = false;            // on the (time, disagreement) front of its backend
  double mrays_per_s() const { return median_s > 0 ? rays / median_s * 1e-6 : 0; }
  double rate() const { return compared > 0 ? disagree / compared : 0; }
};

std::vector<ErrorVariant> default_error_variants();
// scene: must hold curves (the reference surface); rays: e.g. camera rays.
std::vector<ErrorRow> run_error_bench(const Scene& scene, const std::vector<ErrorVariant>& variants,
                                      const BenchOptions& opt, BackendPool& pool);
Table error_table(const std::vector<ErrorRow>& rows);
nlohmann::json error_json(const std::vector<ErrorRow>& rows);

} // namespace masq
