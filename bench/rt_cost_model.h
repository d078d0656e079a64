// What RT hardware would make of the measured counters. On an RT GPU the node tests and
// instance transforms run in fixed function, while every intersector call leaves the
// traversal unit and runs as software on the shader cores. The model prices a ray as
//   cost = node_visits * node + transforms * transform + intersector_calls * isect
// in units of one hardware node visit, so the masquerade's predicted effect on such a
// GPU, cost(ref) / cost(masq), sits beside its measured effect on this device. The
// software/hardware price ratio `isect` is an assumption, not a measurement: the bench
// calibrates it on the one fig3 cell whose RTX speedup the masquerade paper states, and
// prints the limit isect -> infinity (the intersector-call ratio) beside it.
#pragma once
#include "bench/bench_runner.h"

namespace masq {

struct RtCostModel {
  double node = 1.0;      // one wide-node visit (box tests in fixed function)
  double transform = 1.0; // one instance ray transform (fixed function)
  double isect = 16.0;    // one software intersector call
};

struct RtCost {
  double hardware = 0; // node visits and transforms, priced
  double software = 0; // intersector calls, priced
  double total() const { return hardware + software; }
};

// Only for rows with counters (not rayquery or rtpipeline: the driver's traversal is not observable).
RtCost rt_cost(const BenchRow& row, const RtCostModel& model);
// cost(ref) / cost(masq): the speedup the model predicts for RT hardware.
double rt_predicted_speedup(const BenchRow& ref, const BenchRow& masq, const RtCostModel& model);
// The isect price at which the model's predicted speedup for (ref, masq) equals `target`
// (bisection over [0, 1e6]); negative when no price reaches it.
double rt_calibrate_isect(const BenchRow& ref, const BenchRow& masq, double target);

} // namespace masq
