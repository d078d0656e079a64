#include "bench/peer_builds.h"
#include "host/backend.h"
#include "peers/embree_peer.h"
#include <functional>
#include <memory>

namespace masq {

PeerBuildTimes time_peer_builds(const Scene& scene, const AccelOptions& accel, int threads, bool robust, int warmup,
                                int rounds) {
  PeerBuildTimes out;
  // One backend for both methods, as a user's process holds one: each set_scene replaces
  // the structure it held, as the next build of an application would.
  std::unique_ptr<Backend> cpu = make_backend("cpu");
  auto masq_build = [&](Method m) {
    return [&, m] {
      PackedScene ps = build_accel(scene, m, accel);
      cpu->set_scene(ps);
    };
  };
  std::vector<std::function<void()>> builds = {masq_build(Method::Ref), masq_build(Method::Masq)};
  std::unique_ptr<EmbreePeer> embree;
  out.embree_error = EmbreePeer::unavailable_reason();
  if (out.embree_error.empty()) {
    try {
      embree = std::make_unique<EmbreePeer>(threads);
      builds.push_back([&] { embree->set_scene(scene, robust); });
    } catch (const std::exception& e) {
      out.embree_error = e.what();
    }
  }
  std::vector<std::vector<TraceClock>> times = time_round_by_round(builds, warmup, rounds);
  out.ref = times[0];
  out.masq = times[1];
  if (times.size() > 2) out.embree = times[2];
  return out;
}

} // namespace masq
