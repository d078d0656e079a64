// The on-device price fit (bench/price_fit.h) of a results.json already written: the
// rows every suite kept (fig3's cells, table1's cases) read back into BenchRows, and per
// backend the fitted prices with their leave-one-out error, so a committed run (the
// repository's quick run, a GPU run's fig3.json) can be scored without tracing again.
#pragma once
#include "bench/table.h"
#include "bench/bench_runner.h"
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace masq {

// The rows of one results row list (bench_row_json's form); rows that did not run keep
// `unavailable`, rows without counters keep -1 per counter.
BenchRow bench_row_from_json(const nlohmann::json& j);
// The rows of one suite of a results.json: "fig3" (its cells) or "table1" (its cases);
// other suites do not keep rows. Empty when the suite did not run.
std::vector<BenchRow> result_rows(const nlohmann::json& doc, const std::string& suite);
// Per suite of `doc` with rows and per backend with counters, two model forms: auto's
// (ray, node, transform, isect) and the RT model's (ray, TLAS node, BLAS node, transform,
// isect), each with the fit's error on its rows and each row's leave-one-out error.
Table price_fit_table(const nlohmann::json& doc, const std::string& title);

} // namespace masq
