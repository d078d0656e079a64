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
// The acceptance, robust mode: on every cell, disagreement rate <= max_rate,
// no false culls, no self hits. Returns an empty string when met, else one line per
// failing cell.
std::string stress_failures(const StressReport& r, double max_rate = 1e-4);

} // namespace masq::stress
