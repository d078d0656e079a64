#include "host/cpu/trace_threads.h"
#include <algorithm>
#include <tbb/blocked_range.h>
#include <tbb/info.h>
#include <tbb/parallel_for.h>

namespace masq::cpu {

TraceThreads::TraceThreads(int requested)
    : count_(std::clamp(requested, 1, tbb::info::default_concurrency())), arena_(count_) {}

void TraceThreads::for_chunks(int n, int chunk, const std::function<void(int, int)>& body) {
  if (n <= 0) return;
  const int chunks = (n - 1) / chunk + 1; // n + chunk - 1 could overflow
  // One task per chunk (grain 1, simple_partitioner): a chunk is the unit of balance,
  // as rays differ widely in cost, and its bounds stay multiples of `chunk`.
  arena_.execute([&] {
    tbb::parallel_for(
        tbb::blocked_range<int>(0, chunks, 1),
        [&](const tbb::blocked_range<int>& r) {
          for (int k = r.begin(); k < r.end(); ++k) body(k * chunk, std::min(n, (k + 1) * chunk));
        },
        tbb::simple_partitioner());
  });
}

} // namespace masq::cpu
