// One table the suites share (fig3, table1): for each backend the driver traverses for
// (rayquery: candidates its ray query hands the shader; rtpipeline: intersection-shader
// invocations), the intersector calls per ray of ref and masq, their ratio (the
// masquerade paper's Fig. 10 pattern) and rays/s per method, side by side.
#pragma once
#include "bench/bench_runner.h"
#include "bench/table.h"
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace masq {

// The backends among `backends` the driver traverses for, in their order.
std::vector<std::string> driver_backends(const std::vector<std::string>& backends);

// A row's label cells and the bench rows of that case (all backends and methods).
struct DriverCallsCase {
  std::vector<std::string> label;
  const std::vector<BenchRow>* rows;
};

// Columns per driver-traversal backend among `backends`: "<b> calls ref -> masq (ratio)"
// and "<b> Mrays/s" (every method measured). `set`: the ray set read. Empty (no rows)
// when no such backend ran. `json` gets one entry per case and backend.
Table driver_calls_table(const std::string& title, const std::vector<std::string>& label_header,
                         const std::vector<DriverCallsCase>& cases, const std::vector<std::string>& backends,
                         RaySet set, nlohmann::json& json);

} // namespace masq
