// Tables and JSON of a stress run.
#pragma once
#include "stress/stress_runner.h"
#include <nlohmann/json.hpp>
#include <string>

namespace masq::stress {

// One row per cell: disagreement rate per backend (masq method; ref in the JSON),
// ambiguous share, max/mean |dt|/r, max normal error, false culls, self hits.
std::string stress_matrix(const StressReport& r, Mode mode);
// One row per backend x mode: totals, worst cell, time.
std::string stress_summary(const StressReport& r);
// Disagreements by ray kind (all cells), per mode.
std::string stress_by_kind(const StressReport& r);
nlohmann::json stress_json(const StressReport& r);
// Known limits, measured and bounded separately from the 1e-4 acceptance:
//  - curve, grazing rays: the phantom iteration on rays nearly parallel to the curve
//    converges to a later crossing or none on up to a few % of them (long curves);
//  - curves shorter than 10 radii: the phantom tube assumes a radius of curvature well
//    above r; such blobs are outside its model.
struct Exemption {
  PrimType type;
  bool any_kind;   // true: the whole cell (by length), false: only `kind`
  RayKind kind;
  double below_length_r; // any_kind: cells with length / r below this
  double bound;    // the rate these rays must stay under
  const char* why;
};
const std::vector<Exemption>& stress_exemptions();
std::string stress_exemptions_text();

// The acceptance, robust mode: on every cell, disagreement rate <= max_rate
// over the rays no exemption covers (those stay under the exemption's bound), no
// false culls, no self hits (outside exempt cells). Returns an empty string when met,
// else one line per failing cell.
std::string stress_failures(const StressReport& r, double max_rate = 1e-4);

} // namespace masq::stress
