// The threads the cpu backend and the cpu bv tracer trace on: oneTBB's workers, started
// once per process and shared with the host build (bvh/binary/parallel.h) and with
// Embree (peers/embree_peer.cpp), in a task_arena per tracer of the count it was given.
// An arena rather than tbb::global_control: it bounds this tracer's traces alone, where
// a global_control would be process-wide state (the BVH build, a second tracer with
// another count and a library user's own oneTBB work would all be held to it).
#pragma once
#include <functional>
#include <tbb/task_arena.h>

namespace masq::cpu {

class TraceThreads {
 public:
  // At most `requested` threads, and at most the hardware's: oneTBB gives an arena no
  // more (and says so on stderr), so count() reports what runs.
  explicit TraceThreads(int requested);
  int count() const { return count_; }

  // body(begin, end) for each chunk [k * chunk, min(n, (k + 1) * chunk)) of [0, n), each
  // taken by whichever thread is free: the same chunks whatever the thread count, and
  // each ray is written by one call only, so hits and counters never depend on it.
  void for_chunks(int n, int chunk, const std::function<void(int, int)>& body);

 private:
  int count_;
  tbb::task_arena arena_;
};

} // namespace masq::cpu
