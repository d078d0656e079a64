#include "bench/rt_cost_model.h"

namespace masq {

RtCost rt_cost(const BenchRow& row, const RtCostModel& model) {
  RtCost c;
  c.hardware = (row.tlas_nodes + row.blas_nodes) * model.node + row.transforms * model.transform;
  c.software = row.isect_calls * model.isect;
  return c;
}

double rt_predicted_speedup(const BenchRow& ref, const BenchRow& masq, const RtCostModel& model) {
  double m = rt_cost(masq, model).total();
  return m > 0 ? rt_cost(ref, model).total() / m : 0.0;
}

double rt_calibrate_isect(const BenchRow& ref, const BenchRow& masq, double target) {
  RtCostModel model;
  auto speedup = [&](double isect) {
    model.isect = isect;
    return rt_predicted_speedup(ref, masq, model);
  };
  // The predicted speedup moves monotonically from the hardware-cost ratio (isect = 0)
  // to the intersector-call ratio (isect -> infinity).
  double lo = 0.0, hi = 1e6;
  double f_lo = speedup(lo) - target, f_hi = speedup(hi) - target;
  if (f_lo * f_hi > 0) return -1.0;
  for (int i = 0; i < 200; ++i) {
    double mid = 0.5 * (lo + hi);
    double f = speedup(mid) - target;
    if ((f < 0) == (f_lo < 0)) {
      lo = mid;
      f_lo = f;
    } else {
      hi = mid;
    }
  }
  return 0.5 * (lo + hi);
}

} // namespace masq
