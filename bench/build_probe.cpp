// masq_build_probe: a scene file's build (build_accel, then the cpu backend's set_scene,
// as the peers suite's build table times it) repeated in a function of its own,
// probe_builds, for a profiler to count alone (valgrind's callgrind, or perf record with
// its software clock: these virtual machines expose no hardware counters).
//   masq_build_probe FILE|bundle ref|masq|cluster|auto [w4|w8|q8|o4=w4] [capsule|curve=capsule] [builds=10]
//   valgrind --tool=callgrind --collect-atstart=no --toggle-collect='*probe_builds*'
//     build/bench/masq_build_probe ... (one line)
#include "bench/probe_args.h"
#include "bvh/twolevel/build_accel.h"
#include "host/backend.h"
#include "scenes/curve_tools.h"
#include <chrono>
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

} // namespace

int main(int argc, char** argv) {
  try {
    if (argc < 3)
      throw std::invalid_argument("usage: masq_build_probe FILE|bundle ref|masq|cluster|auto [w4|w8|q8|o4=w4] [capsule|curve=capsule] [builds=10]");
    Scene scene = probe::scene(argv[1]);
    const Method method = probe::method(argv[2]);
    AccelOptions accel;
    accel.builder.kind = Builder::Sah4; // the peers suite's build table
    if (argc > 3) accel.nodes = probe::nodes(argv[3]);
    if (argc > 4 && probe::pick<bool>("primitive", argv[4], {{"capsule", false}, {"curve", true}})) {
      scene = segments_to_curves(scene);
      accel.curve_isect = CurveIsect::Roving;
    }
    const int builds = argc > 5 ? std::atoi(argv[5]) : 10;
    if (builds < 1) throw std::invalid_argument("builds must be at least 1");
    std::unique_ptr<Backend> cpu = make_backend("cpu");
    cpu->set_scene(build_accel(scene, method, accel)); // warm-up, not counted
    const auto t0 = std::chrono::steady_clock::now();
    probe_builds(scene, method, accel, *cpu, builds);
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::printf("%d builds: %.2f ms each (wall)\n", builds, 1e3 * s / builds);
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "masq_build_probe: %s\n", e.what());
    return 1;
  }
}
