// Terminal table, JSON and the masq/ref ratios for a bench run.
#pragma once
#include "bench/bench_runner.h"
#include "bench/rt_cost_model.h"
#include "bench/table.h"
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

namespace masq {
Table bench_table(const std::vector<BenchRow>& rows);
// Per backend and ray set: masq vs ref (speedup, intersector calls, memory, OBB/AABB
// area, and the RT cost model's predicted speedup).
Table bench_ratios(const std::vector<BenchRow>& rows, const RtCostModel& model = {});
nlohmann::json bench_row_json(const BenchRow& row);
nlohmann::json bench_json(const Scene& scene, const BenchOptions& opt, const std::vector<BenchRow>& rows);
// Node formats side by side (rows of several formats, `masq bench --nodes w4,w8,q8`):
// each w8/q8 row against the w4 row of the same backend, method and ray set.
Table bench_node_ratios(const std::vector<BenchRow>& rows);
// The row of one backend, method and ray set (nullptr when missing or unavailable); of
// node format `nodes` when given, else the first of any format.
const BenchRow* find_row(const std::vector<BenchRow>& rows, const std::string& backend, Method m, RaySet set,
                         std::optional<NodeFormat> nodes = std::nullopt);
} // namespace masq
