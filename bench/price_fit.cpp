#include "bench/price_fit.h"
#include <algorithm>
#include <cmath>

namespace masq {

std::optional<PriceFit> fit_prices(const std::vector<BenchRow>& rows, const std::string& backend) {
  // Normal equations of the 3-parameter least squares, in relative error (each row
  // divided by its own time, so fast and slow rows count alike).
  double a[3][3] = {}, b[3] = {};
  std::vector<const BenchRow*> used;
  for (const BenchRow& r : rows) {
    if (r.backend != backend || !r.unavailable.empty() || r.median_s <= 0 || r.rays <= 0) continue;
    if (r.tlas_nodes < 0 || r.blas_nodes < 0 || r.transforms < 0) continue;
    double y = r.median_s / r.rays * 1e9; // ns per ray
    double x[3] = {(r.tlas_nodes + r.blas_nodes) / y, r.transforms / y, r.isect_calls / y};
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) a[i][j] += x[i] * x[j];
      b[i] += x[i];
    }
    used.push_back(&r);
  }
  if (used.size() < 3) return std::nullopt;
  // Cramer's rule (3x3).
  auto det3 = [](double m[3][3]) {
    return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
           m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
  };
  double d = det3(a);
  if (!(std::abs(d) > 0) || !std::isfinite(d)) return std::nullopt;
  double p[3];
  for (int k = 0; k < 3; ++k) {
    double m[3][3];
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) m[i][j] = j == k ? b[i] : a[i][j];
    p[k] = det3(m) / d;
  }
  // A price cannot be negative; a tiny floor keeps the model's ratios finite.
  double node = std::max(p[0], 1e-3);
  PriceFit f;
  f.ns_per_node = node;
  f.prices = {1.0, std::max(p[1], 1e-3) / node, std::max(p[2], 1e-3) / node};
  f.rows = int(used.size());
  for (const BenchRow* r : used) {
    double y = r->median_s / r->rays * 1e9;
    double pred = node * (r->tlas_nodes + r->blas_nodes) + node * f.prices.transform * r->transforms +
                  node * f.prices.isect * r->isect_calls;
    f.max_rel_error = std::max(f.max_rel_error, std::abs(pred - y) / y);
  }
  return f;
}

} // namespace masq
