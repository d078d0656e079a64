#include "bench/report_fit.h"
#include "bench/price_fit.h"
#include "bench/ray_sets.h"
#include "masq/types.h"
#include <fmt/format.h>
#include <set>

namespace masq {

BenchRow bench_row_from_json(const nlohmann::json& j) {
  BenchRow r;
  r.backend = j.at("backend").get<std::string>();
  r.method = method_table.parse(j.at("method").get<std::string>());
  r.ray_set = parse_ray_set(j.at("rays").get<std::string>());
  if (j.contains("unavailable")) {
    r.unavailable = j["unavailable"].get<std::string>();
    return r;
  }
  r.rays = j.at("ray_count").get<double>();
  r.median_s = j.at("trace_seconds").at("median").get<double>();
  const nlohmann::json& p = j.at("per_ray");
  r.tlas_nodes = p.at("tlas_nodes").get<double>();
  r.blas_nodes = p.at("blas_nodes").get<double>();
  r.transforms = p.at("transforms").get<double>();
  r.isect_calls = p.at("isect_calls").get<double>();
  r.hit_fraction = j.value("hit_fraction", 0.0);
  return r;
}

std::vector<BenchRow> result_rows(const nlohmann::json& doc, const std::string& suite) {
  std::vector<BenchRow> rows;
  const nlohmann::json& suites = doc.at("suites");
  if (!suites.contains(suite)) return rows;
  const nlohmann::json& data = suites[suite].at("data");
  const char* list = suite == "fig3" ? "cells" : "cases";
  if (!data.contains(list)) return rows;
  for (const nlohmann::json& item : data[list])
    if (item.contains("results"))
      for (const nlohmann::json& r : item["results"]) rows.push_back(bench_row_from_json(r));
  return rows;
}

namespace {
std::vector<double> auto_form(const BenchRow& r) { return {1.0, r.tlas_nodes + r.blas_nodes, r.transforms, r.isect_calls}; }
} // namespace

Table price_fit_table(const nlohmann::json& doc, const std::string& title) {
  Table t;
  t.title = title;
  t.header = {"suite", "backend", "form", "rows", "ns per term", "fit error median", "left out median", "left out worst"};
  t.left_columns = 3;
  for (const char* suite : {"fig3", "table1"}) {
    std::vector<BenchRow> rows = result_rows(doc, suite);
    std::set<std::string> backends;
    for (const BenchRow& r : rows) backends.insert(r.backend);
    for (const std::string& b : backends)
      for (int form = 0; form < 2; ++form) {
        std::optional<TimeFit> f = fit_time(rows, b, form ? rt_form_terms : auto_form);
        if (!f) continue; // rayquery, rtpipeline: no counters to fit
        std::string ns;
        for (double v : f->ns) ns += fmt::format("{}{:.3g}", ns.empty() ? "" : " : ", v);
        t.add({suite, b, form ? "RT" : "auto", std::to_string(f->rows), ns,
               fmt::format("{:.1f}%", 100 * f->median_rel_error), fmt::format("{:.1f}%", 100 * f->loo_median_rel_error),
               fmt::format("{:.1f}%", 100 * f->loo_max_rel_error)});
      }
  }
  t.notes = {"time per ray = sum of ns x term, least squares in relative error over one suite's rows on one backend "
             "(bench/price_fit.h fit_time); auto: ray : node (TLAS + BLAS) : transform : isect; RT: ray : TLAS node : "
             "BLAS node : transform : isect (bench/rt_cost_model.h's form, node visits and transforms in software); left "
             "out: each row predicted by the prices fitted to the other rows"};
  return t;
}

} // namespace masq
