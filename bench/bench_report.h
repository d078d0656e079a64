// Terminal table, JSON and the masq/ref ratios for a bench run.
#pragma once
#include "bench/bench_runner.h"
#include "bench/rt_cost_model.h"
#include "bench/table.h"
#include <nlohmann/json.hpp>
#include <string>

namespace masq {
Table bench_table(const std::vector<BenchRow>& rows);
// Per backend and ray set: masq vs ref (speedup, intersector calls, memory, OBB/AABB
// area, and the RT cost model's predicted speedup).
Table bench_ratios(const std::vector<BenchRow>& rows, const RtCostModel& model = {});
// The headline (within 100 columns): per backend and ray set, ref's rate, masq against
// ref with the intersector calls it saves, and the fastest method against ref. Rows of
// several builders, node formats or curve intersectors: one line each (they are in the label).
Table bench_headline(const std::vector<BenchRow>& rows);
// Per backend, method and ray set with more than one builder: each builder's SAH
// costs, references per primitive, build time, intersector calls and rays/s, and its
// ratios to the first builder of the run (empty when only one builder ran).
Table bench_builders(const std::vector<BenchRow>& rows);
nlohmann::json bench_row_json(const BenchRow& row);
nlohmann::json bench_json(const Scene& scene, const BenchOptions& opt, const std::vector<BenchRow>& rows);
// "ref", or "ref [sbvh]" for a builder other than the default, "masq (roving)" for a
// curve intersector other than the default.
std::string method_label(const BenchRow& r);
// The ref and masq rows of one backend and ray set (nullptr when missing or unavailable):
// the first builder's, node format's and curve intersector's, the given builder's (any
// format), or the given builder's, node format's and curve intersector's.
const BenchRow* find_row(const std::vector<BenchRow>& rows, const std::string& backend, Method m, RaySet set);
const BenchRow* find_row(const std::vector<BenchRow>& rows, const std::string& backend, Method m, RaySet set, Builder b);
const BenchRow* find_row(const std::vector<BenchRow>& rows, const std::string& backend, Method m, RaySet set, Builder b,
                         NodeFormat nodes, CurveIsect isect = CurveIsect::Phantom);
// Curve intersectors side by side (`masq bench --curve-isect phantom,roving`): each row
// against the phantom row of the same backend, method, builder, format and ray set.
Table bench_curve_isect_ratios(const std::vector<BenchRow>& rows);
// Node formats side by side (rows of several formats, `masq bench --nodes w4,w8,q8`):
// each w8/q8 row against the w4 row of the same backend, method, builder and ray set.
Table bench_node_ratios(const std::vector<BenchRow>& rows);
} // namespace masq
