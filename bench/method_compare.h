// The cluster and auto methods (issue 7) beside ref and masq, for the suites' tables:
// per case and backend, cluster's speedup over ref and auto's rays/s over the better of
// ref and masq (the target: auto is never more than 5% slower than that).
#pragma once
#include "bench/bench_runner.h"
#include "bench/table.h"
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace masq {

// auto builds the structure of the candidate it keeps (ref, masq or cluster) byte for
// byte, so its speed can be read from that candidate's row as well as from its own: the
// two readings differ only by timing noise. Both are tallied.
struct MethodTally {
  int cells = 0;       // (case, backend) pairs where all of ref, masq and auto ran
  int auto_within = 0; // of them, auto's own row >= 0.95 x best(ref, masq)
  double worst = 0;    // smallest auto / best(ref, masq) seen (0: none)
  int kept_within = 0; // by the kept candidate's row (auto's own row when it kept the mix)
  double kept_worst = 0;
};

// "2.10x / 0.97x (masq)" or "n/a": cluster/ref, auto/best(ref, masq), what auto kept;
// counts the cell into `tally`.
std::string method_cell(const std::vector<BenchRow>& rows, const std::string& backend, RaySet set, MethodTally& tally);

// The note under such a table: what the cells mean and how often the target held.
std::string method_note(const MethodTally& tally);

// Whether any per-backend price model could meet the target on these rows: per backend,
// prices fitted to all of them (bench/price_fit.h) choose among ref, masq and cluster
// from the measured counters; the note says in how many cells that choice is within 5%
// and how well the fit explains the times. Also written to `data` per backend.
std::string price_fit_note(const std::vector<std::vector<BenchRow>>& groups, const std::vector<std::string>& backends,
                           nlohmann::json& data);

} // namespace masq
