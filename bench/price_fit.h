// Fits the auto method's cost-model prices (bvh/method_plan.h: CostPrices) to measured
// rows: time per ray = node * (TLAS + BLAS node visits) + transform * transforms +
// isect * intersector calls, by least squares over one backend's rows (every method and
// ray set it ran), then scaled so that node = 1. Rows without counters (rayquery) are
// skipped. Needs rows that vary the three counters independently: ref, masq and
// cluster on the same scene do.
#pragma once
#include "bench/bench_runner.h"
#include "bvh/method_plan.h"
#include <optional>
#include <string>
#include <vector>

namespace masq {

struct PriceFit {
  CostPrices prices;       // node == 1
  double ns_per_node = 0;  // the fitted node price in nanoseconds per ray
  int rows = 0;            // rows used
  double max_rel_error = 0; // of the fit's predicted times
};

// nullopt when the backend has fewer than three usable rows or the system is singular.
std::optional<PriceFit> fit_prices(const std::vector<BenchRow>& rows, const std::string& backend);

} // namespace masq
