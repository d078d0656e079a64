// Method auto chosen by measurement: a pilot sample of the caller's own rays is traced
// through each of auto's candidates (bvh/twolevel/build_accel.h: ref, masq, cluster, the mix) on
// the backend that will trace them, and the fastest is kept. The structure cost model
// (bvh/twolevel/structure_cost.h) counts node visits, transforms and intersector calls, but on
// these devices the time per ray also depends on what it cannot see (memory footprint,
// lanes waiting on each other, coherence; docs/methods.md, "auto by pilot").
#pragma once
#include "bvh/twolevel/build_accel.h"
#include "host/backend.h"
#include <cstddef>
#include <span>
#include <vector>

namespace masq {

struct PilotOptions {
  // Pilot sample (pilot_sample); all rays when there are fewer. Raised to the backend's
  // fill_rays where its device needs more to be busy (a large GPU; host/device_fill.h).
  std::size_t max_rays = 32768;
  int rounds = 5;               // timed traces per candidate after one warm-up; the fastest counts
  // A candidate replaces ref only when its pilot is faster by more than this fraction:
  // ref is the smallest structure, and within timing noise the pilot cannot tell the
  // candidates apart.
  double ref_margin = 0.02;
  // One slot per candidate that already holds it from an earlier pilot of the same
  // candidates (the bench's next ray set): no upload again.
  bool slots_hold_candidates = false;
};

struct PilotResult {
  std::size_t kept = 0;        // index into AutoCandidates::built
  std::vector<double> seconds; // each candidate's fastest pilot trace
  std::size_t rays = 0;        // pilot sample size
  double wall_seconds = 0;     // the pilot's uploads, compiles and traces together
};

// Evenly spaced runs of consecutive rays (consecutive camera rays stay coherent, as in
// the full set), max_rays in all; every ray when there are no more than that.
std::vector<kernel::Ray> pilot_sample(std::span<const kernel::Ray> rays, std::size_t max_rays);

// Times the pilot sample through every candidate with `query` (a mix that is ref's
// structure, AutoCandidates::mix_is_ref, is not among them). With one backend per
// candidate (slots[i] gets candidates.built[i] and keeps it), the candidates' timed
// traces take turns round by round, so a load that comes and goes on a shared machine
// falls on all of them alike; with a single backend each candidate is uploaded in turn
// and timed while it is there (the last one stays uploaded). Throws masq::Error for an
// empty candidate list, too few slots or bad options; a backend's own errors pass through.
PilotResult run_pilot(std::span<Backend* const> slots, const AutoCandidates& candidates,
                      std::span<const kernel::Ray> rays, Query query, const PilotOptions& opt = {});
PilotResult run_pilot(Backend& be, const AutoCandidates& candidates, std::span<const kernel::Ray> rays, Query query,
                      const PilotOptions& opt = {});

} // namespace masq
