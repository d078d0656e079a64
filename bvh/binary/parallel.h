// The host build's threads (docs/builders.md, "Parallel host build"). Everything the
// builders run in parallel goes through these three calls, so the thread library
// (oneTBB) stays a private detail of parallel.cpp and the rules that keep the result
// independent of the thread count hold in one place:
//  - parallel work writes only its own slots (an index, a range, a subtree); nothing is
//    appended in completion order;
//  - sums of floats are formed afterwards, in the serial order; only min/max (exact and
//    order-free) are merged across threads.
#pragma once
#include <cstddef>
#include <functional>

namespace masq {

// Runs `body` with at most `threads` threads for the parallel calls below (made from
// it, on any thread it starts): 0 means every hardware thread (as does a count above
// that), 1 runs everything on the calling thread. Throws masq::Error for a negative count; exceptions of `body` pass.
void run_with_build_threads(int threads, const std::function<void()>& body);

// body(begin, end) over [0, n) in chunks of about `grain` indices (>= 1), possibly at once.
void parallel_chunks(std::size_t n, std::size_t grain, const std::function<void(std::size_t, std::size_t)>& body);

// Runs both, possibly at once; returns when both are done.
void parallel_pair(const std::function<void()>& a, const std::function<void()>& b);

// The thread count the parallel calls may use here (1 inside a serial run).
int build_concurrency();

} // namespace masq
