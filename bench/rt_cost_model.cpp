#include "bench/rt_cost_model.h"
#include <fmt/format.h>

namespace masq {

const char* rt_term_name(int term) {
  static const char* names[kRtTerms] = {"ray", "tlas_node", "blas_node", "transform", "isect", "hit"};
  return term >= 0 && term < kRtTerms ? names[term] : "?";
}

RtCounters rt_counters(const BenchRow& row) {
  return {1.0, row.tlas_nodes, row.blas_nodes, row.transforms, row.isect_calls, row.hit_fraction};
}

double rt_cost(const RtCounters& x, const RtCostModel& model) {
  double c = 0;
  for (int k = 0; k < kRtTerms; ++k) c += model.price[k] * x[k];
  return c;
}

double rt_predicted_speedup(const RtCounters& ref, const RtCounters& masq, const RtCostModel& model) {
  double m = rt_cost(masq, model);
  return m > 0 ? rt_cost(ref, model) / m : 0.0;
}

double rt_predicted_speedup(const BenchRow& ref, const BenchRow& masq, const RtCostModel& model) {
  return rt_predicted_speedup(rt_counters(ref), rt_counters(masq), model);
}

std::string rt_speedup_label(double speedup, const RtCostModel& model) {
  if (!(speedup > 0)) return "n/a";
  if (!model.fitted || model.loo_median < 0) return fmt::format("{:.2f}x", speedup);
  return fmt::format("{:.2f}x +-{:.0f}%", speedup, 100 * model.loo_median);
}

std::string rt_model_note(const RtCostModel& model) {
  std::string prices;
  for (int k = 0; k < kRtTerms; ++k) prices += fmt::format("{}{} {:.3g}", k ? ", " : "", rt_term_name(k), model.price[k]);
  if (!model.fitted) return fmt::format("RT model speedup: cost(ref)/cost(masq) with prices per ray counter ({}); {} "
                                        "(bench/rt_cost_model.h)", prices, model.source);
  return fmt::format("RT model speedup: cost(ref)/cost(masq) with prices per ray counter in intersector calls ({}), {} "
                     "({} free prices for {} cells); cells left out of the fit were predicted within {:.1f}% (median), "
                     "{:.1f}% (worst); +-: the median (bench/rt_cost_model.h)",
                     prices, model.source, model.free_parameters, model.cells, 100 * model.loo_median,
                     100 * model.loo_max);
}

} // namespace masq
