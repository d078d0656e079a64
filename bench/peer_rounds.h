// Tracers timed side by side, as the peers suite compares masq with Embree: round by
// round, every tracer once per round, so that a load that comes and goes on a shared
// machine falls on all of them alike. Each trace is timed by the wall clock and by the
// process's CPU time (every thread's: masq's cpu backend, PoCL's and Embree's workers all
// run in this process), the figure that still decides when other jobs share the cores.
#pragma once
#include <chrono>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace masq {

struct TraceClock {
  double wall = 0; // seconds
  double cpu = 0;  // seconds of CPU time, all of the process's threads
};

// Median and range of a set of figures (one per round).
struct Spread {
  double median = 0, min = 0, max = 0;
  nlohmann::json json() const { return {{"median", median}, {"min", min}, {"max", max}}; }
};
Spread spread_of(std::vector<double> v); // empty: all 0

// times[t][k]: tracer t's trace in timed round k. The order of the tracers rotates from
// round to round (round k starts with tracer k mod n), so none always follows the same
// one; `pause` passes before each trace so the workers of the trace before (oneTBB's
// and PoCL's spin a while after a parallel loop returns) are asleep and their spinning
// is not billed to the next tracer's CPU time. warmup rounds first, not kept.
std::vector<std::vector<TraceClock>> time_round_by_round(const std::vector<std::function<void()>>& tracers,
                                                         int warmup, int rounds,
                                                         std::chrono::milliseconds pause = std::chrono::milliseconds(30));

// Per round, what[k] = f(a[k], b[k]): the paired ratios of two tracers' rounds.
std::vector<double> per_round(const std::vector<TraceClock>& a, const std::vector<TraceClock>& b,
                              double (*f)(const TraceClock&, const TraceClock&));

} // namespace masq
