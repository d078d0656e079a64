// The RT model's prices fitted to the masquerade paper's Fig. 3: its 16 cells' RTX 8000
// speedups (bench/paper_figures.h) against masq's counters on the same bundles
// (bench/rt_fit.h does the fit). The fig3 suite fits on the rows it measured; a plain
// `masq bench` measures the cells' counters itself on the cpu backend first (a second or
// two), so every printed RT-model speedup uses fitted prices, never assumed ones.
#pragma once
#include "bench/backend_pool.h"
#include "bench/rt_fit.h"
#include <functional>
#include <nlohmann/json.hpp>
#include <optional>
#include <vector>

namespace masq {

// One of the paper's Fig. 3 cells with the rows masq measured on its bundle.
struct Fig3Rows {
  int n = 0;
  float r = 0;
  double tilt = 0;
  const std::vector<BenchRow>* rows = nullptr;
};

// The fit's options: every counter term, non-negative prices (hardware charges none below zero).
RtFitOptions rt_paper_fit_options();

// The cells with the paper's figure and a ref and masq row with counters (primary rays),
// fitted; nullopt when too few such cells ran.
std::optional<RtFit> fit_rt_to_paper_fig3(const std::vector<Fig3Rows>& cells);

// Traces the paper's 16 bundles on the cpu backend (side x side orthographic primary rays, as fig3 --quick;
// ref and masq, counters only) and fits; nullopt when the cpu backend cannot run.
std::optional<RtFit> measure_and_fit_rt_fig3(BackendPool& pool, int side = 96);

// The fit for results.json: prices and their jackknife errors, free parameters against
// cells, the per-cell predictions (all cells and left out) and the error summaries.
nlohmann::json rt_fit_json(const std::optional<RtFit>& fit);

} // namespace masq
