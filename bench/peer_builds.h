// Build times against Embree's, as the peers suite reports them: masq's ref and masq
// structures (host build, then the cpu backend's upload of it) and Embree's scene (its
// geometry and every BVH build, rtcCommitScene), each alone and round by round
// (bench/peer_rounds.h), so that the ratios are measured on one state of the machine.
// The bench's own rows time a build once, beside whatever else the run does then.
#pragma once
#include "bench/peer_rounds.h"
#include "bvh/twolevel/build_accel.h"
#include "scenes/scene.h"
#include <string>
#include <vector>

namespace masq {

struct PeerBuildTimes {
  std::vector<TraceClock> ref, masq, embree; // one per timed round; embree empty without Embree
  std::string embree_error;                  // why Embree did not build, "" when it did
};

// threads: Embree's worker threads (the cpu backend's and masq's host build use all of
// oneTBB's). robust: Embree's RTC_SCENE_FLAG_ROBUST beside masq's robust mode.
PeerBuildTimes time_peer_builds(const Scene& scene, const AccelOptions& accel, int threads, bool robust, int warmup,
                                int rounds);

} // namespace masq
