// What RT hardware would make of the measured counters. On an RT GPU the node tests and
// instance transforms run in fixed function, while every intersector call leaves the
// traversal unit and runs as software on the shader cores; ray generation, the miss or
// hit shader and the write-back cost the same for every structure. The model prices a
// ray by its counters,
//   cost = ray + tlas * TLAS node visits + blas * BLAS node visits
//        + transform * instance transforms + isect * intersector calls + hit * hits,
// so the masquerade's predicted effect on such a GPU, cost(ref) / cost(masq), sits beside
// its measured effect on this device. A speedup does not change when every price is
// scaled, so prices are in units of one intersector call (isect = 1). They are fitted to
// the masquerade paper's Fig. 3 speedups from masq's own counters on the same bundles
// (bench/rt_fit.h, bench/rt_paper_fit.h), and the fit's leave-one-out error travels with
// them so every printed prediction carries its error.
#pragma once
#include "bench/bench_runner.h"
#include <array>
#include <string>

namespace masq {

enum RtTerm { RtRay, RtTlasNode, RtBlasNode, RtTransform, RtIsect, RtHit, kRtTerms };

// The term names, for tables and JSON ("ray", "tlas_node", ...).
const char* rt_term_name(int term);

// One structure's counters per ray, in the order of RtTerm (RtRay is 1).
using RtCounters = std::array<double, kRtTerms>;
// Only for rows with counters (not rayquery or rtpipeline: the driver's traversal is not observable).
RtCounters rt_counters(const BenchRow& row);

struct RtCostModel {
  // Until a fit replaces them: the old guess (node visits and transforms 1/16 of a call).
  std::array<double, kRtTerms> price{0.0, 1.0 / 16, 1.0 / 16, 1.0 / 16, 1.0, 0.0};
  bool fitted = false;
  // The fit's leave-one-out relative error on its cells (median, largest); < 0: not fitted.
  double loo_median = -1, loo_max = -1;
  int free_parameters = 0, cells = 0; // of the fit: prices fitted (isect = 1 is not) against cells
  std::string source = "not fitted: node visits and transforms priced at 1/16 of an intersector call";
};

double rt_cost(const RtCounters& x, const RtCostModel& model);
// cost(ref) / cost(masq): the speedup the model predicts for RT hardware (0: no cost).
double rt_predicted_speedup(const RtCounters& ref, const RtCounters& masq, const RtCostModel& model);
double rt_predicted_speedup(const BenchRow& ref, const BenchRow& masq, const RtCostModel& model);
// "2.31x +-7%": the prediction with the fit's median leave-one-out error (none if unfitted).
std::string rt_speedup_label(double speedup, const RtCostModel& model);
// One line saying what the prices are and how well they predicted cells left out of their fit.
std::string rt_model_note(const RtCostModel& model);

} // namespace masq
