#include "bvh/binary/parallel.h"
#include "masq/error.h"
#include <algorithm>
#include <string>
#include <tbb/blocked_range.h>
#include <tbb/info.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>
#include <tbb/task_arena.h>

// oneTBB rather than OpenMP: its work stealing nests (a parallel BLAS build inside a
// parallel loop over geometries, subtree tasks inside both) without oversubscribing,
// and a task_arena bounds the threads of one build without touching process-wide state
// (the cpu backend and a library user's own threads are left alone).

namespace masq {

void run_with_build_threads(int threads, const std::function<void()>& body) {
  if (threads < 0) throw Error("build: thread count " + std::to_string(threads) + " (0: all hardware threads, 1: serial)");
  // More threads than the hardware has would only be refused by oneTBB (with a warning
  // on stderr): the arena gets at most that many.
  int hardware = tbb::info::default_concurrency();
  tbb::task_arena arena(threads == 0 ? hardware : std::min(threads, hardware));
  arena.execute(body);
}

void parallel_chunks(std::size_t n, std::size_t grain, const std::function<void(std::size_t, std::size_t)>& body) {
  if (n == 0) return;
  if (grain < 1) grain = 1;
  if (n <= grain || build_concurrency() == 1) {
    body(0, n);
    return;
  }
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, grain),
                    [&](const tbb::blocked_range<std::size_t>& r) { body(r.begin(), r.end()); });
}

void parallel_pair(const std::function<void()>& a, const std::function<void()>& b) {
  if (build_concurrency() == 1) {
    a();
    b();
    return;
  }
  tbb::parallel_invoke(a, b);
}

int build_concurrency() { return tbb::this_task_arena::max_concurrency(); }

} // namespace masq
