#include "bench/rt_fit.h"
#include "bench/price_fit.h"
#include <algorithm>
#include <cmath>

namespace masq {

namespace {

// One reweighted fit with the terms in `active` priced (RtIsect among them, fixed at 1).
std::optional<std::array<double, kRtTerms>> fit_active(const std::vector<RtCell>& cells, const std::vector<int>& active) {
  std::array<double, kRtTerms> p{};
  for (int k : active) p[k] = 1.0;
  std::vector<int> free;
  for (int k : active)
    if (k != RtIsect) free.push_back(k);
  for (int iter = 0; iter < 100; ++iter) {
    std::vector<LinearRow> eq;
    for (const RtCell& c : cells) {
      double ref_cost = 0;
      for (int k = 0; k < kRtTerms; ++k) ref_cost += p[k] * c.ref[k];
      // Until the prices settle a cost can come out <= 0; weigh such a cell as 1.
      double w = ref_cost > 0 ? 1.0 / ref_cost : 1.0;
      LinearRow r;
      for (int k : free) r.x.push_back(c.measured * c.masq[k] - c.ref[k]);
      r.y = -(c.measured * c.masq[RtIsect] - c.ref[RtIsect]);
      r.w = w;
      eq.push_back(r);
    }
    std::optional<std::vector<double>> sol = fit_linear(eq);
    if (!sol) return std::nullopt;
    double change = 0;
    for (std::size_t i = 0; i < free.size(); ++i) {
      change = std::max(change, std::abs((*sol)[i] - p[free[i]]) / std::max(1.0, std::abs((*sol)[i])));
      p[free[i]] = (*sol)[i];
    }
    if (change < 1e-12) break;
  }
  return p;
}

double predict(const std::array<double, kRtTerms>& p, const RtCell& c) {
  double r = 0, m = 0;
  for (int k = 0; k < kRtTerms; ++k) {
    r += p[k] * c.ref[k];
    m += p[k] * c.masq[k];
  }
  return m > 0 ? r / m : 0.0;
}

} // namespace

std::optional<std::array<double, kRtTerms>> fit_rt_prices(const std::vector<RtCell>& cells, const RtFitOptions& opt) {
  std::vector<int> active;
  for (int k = 0; k < kRtTerms; ++k)
    if (opt.terms[k] || k == RtIsect) active.push_back(k);
  for (;;) {
    std::optional<std::array<double, kRtTerms>> p = fit_active(cells, active);
    if (!p || !opt.nonnegative) return p;
    int worst = -1;
    for (int k : active)
      if ((*p)[k] < 0 && (worst < 0 || (*p)[k] < (*p)[worst])) worst = k;
    if (worst < 0) return p;
    active.erase(std::find(active.begin(), active.end(), worst));
  }
}

std::optional<RtFit> fit_rt_model(const std::vector<RtCell>& cells, const RtFitOptions& opt, const std::string& source) {
  std::optional<std::array<double, kRtTerms>> all = fit_rt_prices(cells, opt);
  if (!all) return std::nullopt;
  RtFit f;
  f.cells = int(cells.size());
  f.model.price = *all;
  f.model.fitted = true;
  f.model.source = source;
  for (int k = 0; k < kRtTerms; ++k) {
    f.priced[k] = k == RtIsect || (opt.terms[k] && (*all)[k] != 0.0);
    f.free_parameters += f.priced[k] && k != RtIsect;
  }
  std::vector<std::array<double, kRtTerms>> loo_prices;
  std::vector<double> fit_err, loo_err;
  for (std::size_t i = 0; i < cells.size(); ++i) {
    std::vector<RtCell> rest = cells;
    rest.erase(rest.begin() + std::ptrdiff_t(i));
    std::optional<std::array<double, kRtTerms>> q = fit_rt_prices(rest, opt);
    if (!q) return std::nullopt;
    loo_prices.push_back(*q);
    RtCellResult r{cells[i].label, cells[i].measured, predict(*all, cells[i]), predict(*q, cells[i])};
    fit_err.push_back(r.measured > 0 ? r.fitted / r.measured - 1 : 0);
    loo_err.push_back(r.loo_error());
    f.per_cell.push_back(r);
  }
  f.model.free_parameters = f.free_parameters;
  f.model.cells = f.cells;
  std::tie(f.fit_median, f.fit_max) = median_and_max_abs(fit_err);
  std::tie(f.model.loo_median, f.model.loo_max) = median_and_max_abs(loo_err);
  // Jackknife: the spread of the leave-one-out prices, scaled by (n - 1) / n.
  const double n = double(loo_prices.size());
  for (int k = 0; k < kRtTerms; ++k) {
    double mean = 0, ss = 0;
    for (const auto& q : loo_prices) mean += q[k] / n;
    for (const auto& q : loo_prices) ss += (q[k] - mean) * (q[k] - mean);
    f.price_error[k] = n > 1 ? std::sqrt((n - 1) / n * ss) : 0.0;
  }
  return f;
}

} // namespace masq
