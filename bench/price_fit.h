// Linear price models fitted to measured counters, and the one least-squares solver both
// of masq's price fits use:
// - fit_prices: the auto method's cost-model prices (bvh/twolevel/method_plan.h:
//   CostPrices) from one backend's rows: time per ray = ray + node * (TLAS + BLAS node
//   visits) + transform * transforms + isect * intersector calls, then scaled so that
//   node = 1. `ray` (set-up, hit write-back) is the same for every structure, so it does
//   not enter auto's choice, but leaving it out pushes its cost into the other prices.
//   Rows without counters (rayquery, rtpipeline) are skipped. Needs rows that vary the
//   counters independently: ref, masq and cluster on the same scene do.
// - bench/rt_fit.h: the RT model's prices from the paper's speedups (a ratio of two such
//   sums, fitted by reweighted least squares through fit_linear).
#pragma once
#include "bench/bench_runner.h"
#include "bvh/twolevel/method_plan.h"
#include <optional>
#include <string>
#include <vector>

namespace masq {

// One equation of a weighted linear least squares: sum_k p_k x[k] ~ y, weighted by w.
struct LinearRow {
  std::vector<double> x;
  double y = 0;
  double w = 1;
};

// The prices p minimising sum w^2 (p.x - y)^2 over `rows`, any number of terms (all rows
// as long as the first); nullopt with fewer rows than terms or a singular system.
std::optional<std::vector<double>> fit_linear(const std::vector<LinearRow>& rows);

// Time per ray = sum_k ns[k] x term k of the row, least squares in relative error over
// one backend's usable rows (rows with counters and a time), and each row's error when
// predicted by the fit to the other rows (leave-one-out).
struct TimeFit {
  std::vector<double> ns; // per term, nanoseconds per unit of the term
  int rows = 0;
  double median_rel_error = 0, max_rel_error = 0;
  double loo_median_rel_error = -1, loo_max_rel_error = -1; // < 0: too few rows
};
using TimeTerms = std::vector<double> (*)(const BenchRow&);
std::optional<TimeFit> fit_time(const std::vector<BenchRow>& rows, const std::string& backend, TimeTerms terms);
// The RT model's terms (bench/rt_cost_model.h: ray, TLAS nodes, BLAS nodes, transforms,
// intersector calls; hits left out as there): the on-device form of the RT model.
std::vector<double> rt_form_terms(const BenchRow& r);

struct PriceFit {
  CostPrices prices;       // node == 1
  double ns_per_node = 0;  // the fitted node price in nanoseconds per ray
  double ns_per_ray = 0;   // the fitted constant per ray
  int rows = 0;            // rows used
  double median_rel_error = 0, max_rel_error = 0; // of the fit's predicted times, on the rows it was fitted to
  // Each row predicted by the prices fitted to the other rows (leave-one-out): the error
  // a new row should expect. Negative when too few rows are left to fit.
  double loo_median_rel_error = -1, loo_max_rel_error = -1;
};

// nullopt when the backend has fewer than four usable rows or the system is singular.
// Prices come out as fitted, negative ones included: a negative price says the
// counters do not explain the times, which is what the fit is there to show.
std::optional<PriceFit> fit_prices(const std::vector<BenchRow>& rows, const std::string& backend);

// How well a linear price model can choose at all: per group of rows (one scene and
// ray set each), the structure among ref, masq and cluster that the fitted prices
// rank cheapest from the MEASURED counters (the best a counter model can do; auto's
// model has to predict them), and whether that one is within 5% of the faster of ref
// and masq.
struct FitChoices {
  int cells = 0, within = 0;
};
FitChoices fit_choices(const std::vector<std::vector<BenchRow>>& groups, const std::string& backend, const PriceFit& fit);

// Median and largest of |v| (0, 0 for an empty list).
std::pair<double, double> median_and_max_abs(std::vector<double> v);

} // namespace masq
