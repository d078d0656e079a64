#include "bench/price_fit.h"
#include "bench/bench_report.h"
#include <algorithm>
#include <cmath>

namespace masq {

namespace {

constexpr int kTerms = 4; // ray, node, transform, isect

bool usable(const BenchRow& r, const std::string& backend) {
  return r.backend == backend && r.unavailable.empty() && r.median_s > 0 && r.rays > 0 && r.tlas_nodes >= 0 &&
         r.blas_nodes >= 0 && r.transforms >= 0;
}

double ns_per_ray(const BenchRow& r) { return r.median_s / r.rays * 1e9; }

std::array<double, kTerms> terms(const BenchRow& r) {
  return {1.0, r.tlas_nodes + r.blas_nodes, r.transforms, r.isect_calls};
}

double predict(const PriceFit& f, const BenchRow& r) {
  std::array<double, kTerms> x = terms(r);
  return f.ns_per_ray + f.ns_per_node * (x[1] + f.prices.transform * x[2] + f.prices.isect * x[3]);
}

// Solves a x = b (4x4) by Gaussian elimination with partial pivoting; false if singular.
bool solve(double a[kTerms][kTerms], double b[kTerms], double x[kTerms]) {
  for (int c = 0; c < kTerms; ++c) {
    int p = c;
    for (int r = c + 1; r < kTerms; ++r)
      if (std::abs(a[r][c]) > std::abs(a[p][c])) p = r;
    if (!(std::abs(a[p][c]) > 1e-300)) return false;
    std::swap(a[p], a[c]);
    std::swap(b[p], b[c]);
    for (int r = c + 1; r < kTerms; ++r) {
      double f = a[r][c] / a[c][c];
      for (int k = c; k < kTerms; ++k) a[r][k] -= f * a[c][k];
      b[r] -= f * b[c];
    }
  }
  for (int c = kTerms - 1; c >= 0; --c) {
    double s = b[c];
    for (int k = c + 1; k < kTerms; ++k) s -= a[c][k] * x[k];
    x[c] = s / a[c][c];
  }
  return std::all_of(x, x + kTerms, [](double v) { return std::isfinite(v); });
}

} // namespace

std::optional<PriceFit> fit_prices(const std::vector<BenchRow>& rows, const std::string& backend) {
  // Normal equations of the least squares in relative error (each row divided by its
  // own time, so fast and slow rows count alike).
  double a[kTerms][kTerms] = {}, b[kTerms] = {};
  std::vector<const BenchRow*> used;
  for (const BenchRow& r : rows) {
    if (!usable(r, backend)) continue;
    double y = ns_per_ray(r);
    std::array<double, kTerms> x = terms(r);
    for (int i = 0; i < kTerms; ++i) {
      for (int j = 0; j < kTerms; ++j) a[i][j] += x[i] / y * x[j] / y;
      b[i] += x[i] / y;
    }
    used.push_back(&r);
  }
  double p[kTerms];
  if (used.size() < std::size_t(kTerms) || !solve(a, b, p)) return std::nullopt;
  // Relative prices need a positive node price to divide by.
  double node = std::abs(p[1]) > 1e-9 ? p[1] : 1e-9;
  PriceFit f;
  f.ns_per_ray = p[0];
  f.ns_per_node = node;
  f.prices = {1.0, p[2] / node, p[3] / node};
  f.rows = int(used.size());
  std::vector<double> err;
  for (const BenchRow* r : used) err.push_back(std::abs(predict(f, *r) - ns_per_ray(*r)) / ns_per_ray(*r));
  std::sort(err.begin(), err.end());
  f.median_rel_error = err[err.size() / 2];
  f.max_rel_error = err.back();
  return f;
}

FitChoices fit_choices(const std::vector<std::vector<BenchRow>>& groups, const std::string& backend, const PriceFit& fit) {
  FitChoices out;
  for (const std::vector<BenchRow>& rows : groups)
    for (RaySet set : {RaySet::Primary, RaySet::Shadow, RaySet::Diffuse}) {
      const BenchRow* ref = find_row(rows, backend, Method::Ref, set);
      const BenchRow* masq = find_row(rows, backend, Method::Masq, set);
      const BenchRow* cluster = find_row(rows, backend, Method::Cluster, set);
      if (!ref || !masq || !cluster || !usable(*ref, backend) || !usable(*masq, backend) || !usable(*cluster, backend))
        continue;
      const BenchRow* pick = ref;
      for (const BenchRow* r : {masq, cluster})
        if (predict(fit, *r) < predict(fit, *pick)) pick = r;
      out.cells++;
      out.within += ns_per_ray(*pick) <= 1.05 * std::min(ns_per_ray(*ref), ns_per_ray(*masq));
    }
  return out;
}

} // namespace masq
