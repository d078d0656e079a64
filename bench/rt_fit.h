// Fits the RT model's prices (bench/rt_cost_model.h) to measured speedups: each cell is a
// pair of structures (ref, masq) with their counters per ray and the speedup some device
// measured for them, and the model predicts cost(ref) / cost(masq). Prices are in units
// of one intersector call, so a model with k priced terms besides the call has k free
// parameters. The ratio is fitted by iteratively reweighted linear least squares through
// bench/price_fit.h's fit_linear: measured * cost(masq) - cost(ref) = 0 is linear in the
// prices, and dividing each cell's equation by its current cost(ref) makes the residual
// the relative error of the predicted speedup.
#pragma once
#include "bench/rt_cost_model.h"
#include <optional>
#include <string>
#include <vector>

namespace masq {

struct RtCell {
  std::string label;
  RtCounters ref{}, masq{};
  double measured = 0; // speedup, time(ref) / time(masq)
};

struct RtFitOptions {
  // The terms that get a price (the rest cost 0); the intersector call is always priced (1).
  std::array<bool, kRtTerms> terms{true, true, true, true, true, false};
  // Hardware cannot charge a negative price: drop the most negative term and refit
  // until none is left (the dropped terms then cost 0).
  bool nonnegative = true;
};

struct RtCellResult {
  std::string label;
  double measured = 0;
  double fitted = 0; // predicted by the fit to all cells
  double loo = 0;    // predicted by the fit to the other cells
  double loo_error() const { return measured > 0 ? loo / measured - 1 : 0; }
};

struct RtFit {
  RtCostModel model; // prices, fitted = true, loo_median / loo_max set
  std::array<double, kRtTerms> price_error{}; // jackknife standard error of each price, from the leave-one-out fits
  std::array<bool, kRtTerms> priced{};         // the terms left with a price (nonnegative may drop some)
  int free_parameters = 0, cells = 0;
  std::vector<RtCellResult> per_cell;
  double fit_median = 0, fit_max = 0; // relative error on the cells fitted to
};

// The prices alone (isect = 1); nullopt when the cells cannot determine them.
std::optional<std::array<double, kRtTerms>> fit_rt_prices(const std::vector<RtCell>& cells, const RtFitOptions& opt);

// The fit, each cell's leave-one-out prediction and the prices' uncertainty; nullopt when
// the fit to all cells, or to any leave-one-out subset, is undetermined.
std::optional<RtFit> fit_rt_model(const std::vector<RtCell>& cells, const RtFitOptions& opt, const std::string& source);

} // namespace masq
