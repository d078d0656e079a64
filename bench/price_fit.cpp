#include "bench/price_fit.h"
#include "bench/bench_report.h"
#include <algorithm>
#include <cmath>

namespace masq {

std::optional<std::vector<double>> fit_linear(const std::vector<LinearRow>& rows) {
  if (rows.empty()) return std::nullopt;
  const std::size_t n = rows[0].x.size();
  if (n == 0 || rows.size() < n) return std::nullopt;
  // Normal equations (a p = b), solved by Gaussian elimination with partial pivoting:
  // the systems are a handful of terms, so conditioning, not speed, is what matters,
  // and the caller scales its terms to comparable sizes.
  std::vector<std::vector<double>> a(n, std::vector<double>(n, 0.0));
  std::vector<double> b(n, 0.0), p(n, 0.0);
  for (const LinearRow& r : rows) {
    if (r.x.size() != n) return std::nullopt;
    for (std::size_t i = 0; i < n; ++i) {
      for (std::size_t j = 0; j < n; ++j) a[i][j] += r.w * r.w * r.x[i] * r.x[j];
      b[i] += r.w * r.w * r.x[i] * r.y;
    }
  }
  double scale = 0;
  for (std::size_t i = 0; i < n; ++i) scale = std::max(scale, std::abs(a[i][i]));
  for (std::size_t c = 0; c < n; ++c) {
    std::size_t piv = c;
    for (std::size_t r = c + 1; r < n; ++r)
      if (std::abs(a[r][c]) > std::abs(a[piv][c])) piv = r;
    // Relative to the largest diagonal: a term no row varies makes the system singular.
    if (!(std::abs(a[piv][c]) > 1e-13 * scale)) return std::nullopt;
    std::swap(a[piv], a[c]);
    std::swap(b[piv], b[c]);
    for (std::size_t r = c + 1; r < n; ++r) {
      double f = a[r][c] / a[c][c];
      for (std::size_t k = c; k < n; ++k) a[r][k] -= f * a[c][k];
      b[r] -= f * b[c];
    }
  }
  for (std::size_t c = n; c-- > 0;) {
    double s = b[c];
    for (std::size_t k = c + 1; k < n; ++k) s -= a[c][k] * p[k];
    p[c] = s / a[c][c];
  }
  if (!std::all_of(p.begin(), p.end(), [](double v) { return std::isfinite(v); })) return std::nullopt;
  return p;
}

std::pair<double, double> median_and_max_abs(std::vector<double> v) {
  if (v.empty()) return {0.0, 0.0};
  for (double& e : v) e = std::abs(e);
  std::sort(v.begin(), v.end());
  double med = v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
  return {med, v.back()};
}

namespace {

bool usable(const BenchRow& r, const std::string& backend) {
  return r.backend == backend && r.unavailable.empty() && r.median_s > 0 && r.rays > 0 && r.tlas_nodes >= 0 &&
         r.blas_nodes >= 0 && r.transforms >= 0;
}

double ns_per_ray(const BenchRow& r) { return r.median_s / r.rays * 1e9; }

// ray, node, transform, isect; weighted by 1/time so that the fit minimises relative
// error and fast and slow rows count alike.
LinearRow time_row(const BenchRow& r) {
  double y = ns_per_ray(r);
  return {{1.0, r.tlas_nodes + r.blas_nodes, r.transforms, r.isect_calls}, y, 1.0 / y};
}

double predict(const PriceFit& f, const BenchRow& r) {
  return f.ns_per_ray + f.ns_per_node * (r.tlas_nodes + r.blas_nodes + f.prices.transform * r.transforms +
                                         f.prices.isect * r.isect_calls);
}

} // namespace

std::optional<TimeFit> fit_time(const std::vector<BenchRow>& rows, const std::string& backend, TimeTerms terms) {
  std::vector<LinearRow> eq;
  for (const BenchRow& r : rows)
    if (usable(r, backend)) {
      double y = ns_per_ray(r);
      eq.push_back({terms(r), y, 1.0 / y}); // weighted by 1/time: relative error, fast and slow rows alike
    }
  std::optional<std::vector<double>> p = fit_linear(eq);
  if (!p) return std::nullopt;
  auto predict_eq = [](const std::vector<double>& q, const LinearRow& e) {
    double s = 0;
    for (std::size_t k = 0; k < q.size(); ++k) s += q[k] * e.x[k];
    return s;
  };
  TimeFit f;
  f.ns = *p;
  f.rows = int(eq.size());
  std::vector<double> err, loo;
  for (std::size_t i = 0; i < eq.size(); ++i) {
    err.push_back(predict_eq(*p, eq[i]) / eq[i].y - 1);
    std::vector<LinearRow> rest = eq;
    rest.erase(rest.begin() + std::ptrdiff_t(i));
    if (std::optional<std::vector<double>> q = fit_linear(rest)) loo.push_back(predict_eq(*q, eq[i]) / eq[i].y - 1);
  }
  std::tie(f.median_rel_error, f.max_rel_error) = median_and_max_abs(err);
  if (loo.size() == eq.size()) std::tie(f.loo_median_rel_error, f.loo_max_rel_error) = median_and_max_abs(loo);
  return f;
}

std::vector<double> rt_form_terms(const BenchRow& r) {
  return {1.0, r.tlas_nodes, r.blas_nodes, r.transforms, r.isect_calls};
}

namespace {
std::vector<double> auto_terms(const BenchRow& r) { return time_row(r).x; }
} // namespace

std::optional<PriceFit> fit_prices(const std::vector<BenchRow>& rows, const std::string& backend) {
  std::optional<TimeFit> t = fit_time(rows, backend, auto_terms);
  if (!t) return std::nullopt;
  const std::vector<double>& p = t->ns;
  // Relative prices need a positive node price to divide by.
  double node = std::abs(p[1]) > 1e-9 ? p[1] : 1e-9;
  PriceFit f;
  f.ns_per_ray = p[0];
  f.ns_per_node = node;
  f.prices = {1.0, p[2] / node, p[3] / node};
  f.rows = t->rows;
  f.median_rel_error = t->median_rel_error;
  f.max_rel_error = t->max_rel_error;
  f.loo_median_rel_error = t->loo_median_rel_error;
  f.loo_max_rel_error = t->loo_max_rel_error;
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
