// The cluster and auto methods (issue 7) beside ref and masq, for the suites' tables:
// per case and backend, cluster's speedup over ref and auto's rays/s over the better of
// ref and masq (the target: auto is never more than 5% slower than that).
#pragma once
#include "bench/bench_runner.h"
#include "bench/table.h"
#include <string>
#include <vector>

namespace masq {

struct MethodTally {
  int cells = 0;      // (case, backend) pairs where all of ref, masq and auto ran
  int auto_within = 0; // of them, auto >= 0.95 x best(ref, masq)
  double worst = 0;    // smallest auto / best(ref, masq) seen (0: none)
};

// "2.10x / 0.97x" or "n/a"; counts the cell into `tally`.
std::string method_cell(const std::vector<BenchRow>& rows, const std::string& backend, RaySet set, MethodTally& tally);

// The note under such a table: what the cells mean and how often the target held.
std::string method_note(const MethodTally& tally);

} // namespace masq
