// Terminal table, JSON and the masq/ref ratios for a bench run.
#pragma once
#include "bench/bench_runner.h"
#include <nlohmann/json.hpp>
#include <string>

namespace masq {
std::string bench_table(const std::vector<BenchRow>& rows);
std::string bench_ratios(const std::vector<BenchRow>& rows); // per backend: masq vs ref
nlohmann::json bench_json(const Scene& scene, const BenchOptions& opt, const std::vector<BenchRow>& rows);
} // namespace masq
