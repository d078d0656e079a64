// masq_build_probe: a scene file's build (build_accel, then the cpu backend's set_scene,
// as the peers suite's build table times it) repeated in a function of its own,
// probe_builds, for a profiler to count alone (valgrind's callgrind, or perf record with
// its software clock: these virtual machines expose no hardware counters).
//   masq_build_probe FILE|bundle ref|masq|cluster|auto|embree|peers [w4|w8|q8|o4=w4] [capsule|curve|thick|thick-curve=capsule] [builds=10]
// (thick: every radius 0.05 x the mean segment, the peers suite's thick rows; embree:
// Embree's scene as the peers suite's build table times it, robust, on 2 threads; peers:
// that table's row itself, ref, masq and Embree round by round (bench/peer_builds.h),
// builds = its rounds after 1 warm-up, medians (min-max) of CPU time and of masq/Embree)
//   valgrind --tool=callgrind --collect-atstart=no --toggle-collect='*probe_builds*'
//     build/bench/masq_build_probe ... (one line)
// It prints the structure's digest (FNV-1a over every array the kernels read): two builds of masq that print the same digest made the same structure,
// byte for byte.
#include "bench/peer_builds.h"
#include "bench/probe_args.h"
#include "bench/process_clock.h"
#include "bvh/twolevel/build_accel.h"
#include "host/backend.h"
#include "kernels/scene_array_table.h"
#include "peers/embree_peer.h"
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <stdexcept>
#include <string>

using namespace masq;

namespace {

__attribute__((noinline)) void probe_builds(const Scene& scene, Method method, const AccelOptions& accel, Backend& cpu,
                                            int builds) {
  for (int i = 0; i < builds; ++i) cpu.set_scene(build_accel(scene, method, accel));
}

__attribute__((noinline)) void probe_embree_builds(const Scene& scene, EmbreePeer& embree, int builds) {
  for (int i = 0; i < builds; ++i) embree.set_scene(scene, true);
}

// FNV-1a (64 bits) over the structure's arrays in the kernels' table order
// (kernels/scene_array_table.h: the rows the backends upload), each array's length first.
std::uint64_t structure_digest(const PackedScene& scene) {
  std::uint64_t h = 1469598103934665603ull;
  auto mix = [&](const void* data, std::size_t n) {
    const std::uint64_t len = n;
    const auto* l = reinterpret_cast<const unsigned char*>(&len);
    for (std::size_t i = 0; i < sizeof len; ++i) h = (h ^ l[i]) * 1099511628211ull;
    const auto* p = static_cast<const unsigned char*>(data);
    for (std::size_t i = 0; i < n; ++i) h = (h ^ p[i]) * 1099511628211ull;
  };
  auto mix_vector = [&](const auto& v) { mix(v.data(), v.size() * sizeof(v[0])); };
#define MASQ_DIGEST_SCENE(name) mix_vector(scene.name);
#define MASQ_DIGEST_PRIM(name) mix_vector(scene.name);
#define MASQ_DIGEST_NODES(name) mix(scene.node_data(), scene.node_bytes());
#define MASQ_DIGEST_BV(name)
#define MASQ_DIGEST_ROW(T, name, b, kernels, source) MASQ_DIGEST_##source(name)
  MASQ_SCENE_ARRAYS(MASQ_DIGEST_ROW)
#undef MASQ_DIGEST_ROW
#undef MASQ_DIGEST_BV
#undef MASQ_DIGEST_NODES
#undef MASQ_DIGEST_PRIM
#undef MASQ_DIGEST_SCENE
  return h;
}

} // namespace

int main(int argc, char** argv) {
  try {
    if (argc < 3)
      throw std::invalid_argument("usage: masq_build_probe FILE|bundle ref|masq|cluster|auto|embree|peers [w4|w8|q8|o4=w4] "
                                  "[capsule|curve|thick|thick-curve=capsule] [builds=10]");
    const probe::Prims prims = argc > 4 ? probe::prims(argv[4]) : probe::Prims{};
    Scene scene = probe::scene(argv[1], prims);
    const bool embree = std::string(argv[2]) == "embree", peers = std::string(argv[2]) == "peers";
    const Method method = embree || peers ? Method::Ref : probe::method(argv[2]);
    AccelOptions accel;
    accel.builder.kind = Builder::Sah4; // the peers suite's build table
    if (argc > 3) accel.nodes = probe::nodes(argv[3]);
    if (prims.curves) accel.curve_isect = CurveIsect::Roving;
    const int builds = argc > 5 ? std::atoi(argv[5]) : 10;
    if (builds < 1) throw std::invalid_argument("builds must be at least 1");
    if (peers) {
      const PeerBuildTimes t = time_peer_builds(scene, accel, 2, true, 1, builds);
      if (!t.embree_error.empty()) throw std::runtime_error(t.embree_error);
      auto cpu_ms = [](const std::vector<TraceClock>& v) {
        std::vector<double> ms;
        for (const TraceClock& c : v) ms.push_back(1e3 * c.cpu);
        return spread_of(ms);
      };
      auto over_embree = [&](const std::vector<TraceClock>& v) {
        return spread_of(per_round(v, t.embree, [](const TraceClock& a, const TraceClock& e) { return a.cpu / e.cpu; }));
      };
      const Spread ref = cpu_ms(t.ref), masq = cpu_ms(t.masq), emb = cpu_ms(t.embree);
      const Spread ref_x = over_embree(t.ref), masq_x = over_embree(t.masq);
      std::printf("%d rounds, CPU ms: ref %.1f (%.1f-%.1f), masq %.1f (%.1f-%.1f), Embree %.1f (%.1f-%.1f); "
                  "ref/Embree %.2fx (%.2f-%.2f), masq/Embree %.2fx (%.2f-%.2f)\n",
                  builds, ref.median, ref.min, ref.max, masq.median, masq.min, masq.max, emb.median, emb.min, emb.max,
                  ref_x.median, ref_x.min, ref_x.max, masq_x.median, masq_x.min, masq_x.max);
      return 0;
    }
    if (embree) {
      if (const std::string why = EmbreePeer::unavailable_reason(); !why.empty()) throw std::runtime_error(why);
      EmbreePeer peer(2);
      peer.set_scene(scene, true); // warm-up, not counted
      const double cpu0 = process_cpu_seconds();
      const auto t0 = std::chrono::steady_clock::now();
      probe_embree_builds(scene, peer, builds);
      const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      std::printf("%d Embree builds: %.2f ms each (wall), %.2f ms each (CPU time, every thread)\n", builds,
                  1e3 * s / builds, 1e3 * (process_cpu_seconds() - cpu0) / builds);
      return 0;
    }
    std::unique_ptr<Backend> cpu = make_backend("cpu");
    cpu->set_scene(build_accel(scene, method, accel)); // warm-up, not counted
    const double cpu0 = process_cpu_seconds();
    const auto t0 = std::chrono::steady_clock::now();
    probe_builds(scene, method, accel, *cpu, builds);
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const double cpu_s = process_cpu_seconds() - cpu0;
    std::printf("%d builds: %.2f ms each (wall), %.2f ms each (CPU time, every thread); structure digest %016llx\n",
                builds, 1e3 * s / builds, 1e3 * cpu_s / builds,
                (unsigned long long)structure_digest(build_accel(scene, method, accel)));
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "masq_build_probe: %s\n", e.what());
    return 1;
  }
}
