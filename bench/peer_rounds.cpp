#include "bench/peer_rounds.h"
#include "bench/process_clock.h"
#include "masq/error.h"
#include <algorithm>
#include <thread>

namespace masq {

Spread spread_of(std::vector<double> v) {
  if (v.empty()) return {};
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  const double median = n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
  return {median, v.front(), v.back()};
}

std::vector<std::vector<TraceClock>> time_round_by_round(const std::vector<std::function<void()>>& tracers,
                                                         int warmup, int rounds, std::chrono::milliseconds pause) {
  if (rounds < 1) throw Error("peers: at least one timed round is needed (got " + std::to_string(rounds) + ")");
  const std::size_t n = tracers.size();
  std::vector<std::vector<TraceClock>> times(n);
  for (int round = -std::max(0, warmup); round < rounds; ++round)
    for (std::size_t k = 0; k < n; ++k) {
      const std::size_t t = (std::size_t(std::max(round, 0)) + k) % n;
      std::this_thread::sleep_for(pause);
      const auto w0 = std::chrono::steady_clock::now();
      const double c0 = process_cpu_seconds();
      tracers[t]();
      const double c1 = process_cpu_seconds();
      const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - w0).count();
      if (round >= 0) times[t].push_back({wall, c1 - c0});
    }
  return times;
}

std::vector<double> per_round(const std::vector<TraceClock>& a, const std::vector<TraceClock>& b,
                              double (*f)(const TraceClock&, const TraceClock&)) {
  std::vector<double> out;
  for (std::size_t k = 0; k < a.size() && k < b.size(); ++k) out.push_back(f(a[k], b[k]));
  return out;
}

} // namespace masq
