// masq_trace_probe: one ray set of a scene file traced on the cpu backend (one thread:
// MASQ_CPU_THREADS=1) or through Embree (on as many threads as the cpu backend), in a function of its own, probe_traces, for
// valgrind's callgrind to count alone: instructions, cache misses (--cache-sim=yes) and
// branch mispredictions (--branch-sim=yes) per ray and per node visit (docs/results.md,
// "Bytes, instructions and branches per ray"). The rays are the bench's: camera rays of
// width x width, and the shadow or diffuse rays from their hits.
// FILE "bundle" is the embedded default scene (the peers suite's bundle row); "bundle-hair" and
// "bundle-ground" keep only its strands or only its ground plane.
//   masq_trace_probe FILE|bundle|bundle-hair|bundle-ground ref|masq|cluster|auto w4|w8|q8|o4 primary|shadow|diffuse [capsule|curve|thick|thick-curve] [masq|embree|embree1m] [width=256] [traces=4] [nearest|starts-last] [repeat=1]
// (nearest|starts-last: AccelOptions::blas_occlusion, the BLAS order of occlusion queries;
// repeat: each ray traced that many times in a row. A repeat finds the ray's nodes and
// primitives in cache and its branches just taken, so with T(k) the time at repeat k,
// (T(k) - T(1)) / (k - 1) is a trace warm and T(1) less that what a cold one adds (cache
// and TLB misses, mispredicted branches). Not for camera rays the cpu takes in packets
// (one BLAS of capsules, a TLAS of capsule or curve entries): a packet would hold a ray
// and its repeats.)
//   valgrind --tool=callgrind --cache-sim=yes --branch-sim=yes --collect-atstart=no
//     --toggle-collect='*probe_traces*' build/bench/masq_trace_probe ... (one line)
#include "bench/backend_pool.h"
#include "bench/bench_runner.h"
#include "bench/probe_args.h"
#include "bench/process_clock.h"
#include "host/backend.h"
#include "masq/knobs.h"
#include "peers/embree_peer.h"
#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <string>
#include <thread>
#include <utility>
#include <vector>

using namespace masq;

namespace {

// The traces counted: traces x the ray set, through masq's backend or Embree.
__attribute__((noinline)) void probe_traces(Backend* be, EmbreePeer* embree, EmbreeTrace how, const RayBatch& b, Query q,
                                            int traces, std::vector<kernel::Hit>& hits, std::vector<std::uint8_t>& occluded) {
  for (int i = 0; i < traces; ++i) {
    if (be) be->trace(b.rays, hits, {}, q);
    else if (q == Query::Any) embree->occluded(b.rays, occluded, how);
    else embree->trace(b.rays, hits, how);
  }
}

} // namespace

int main(int argc, char** argv) {
  try {
    if (argc < 5) throw std::invalid_argument("usage: masq_trace_probe FILE|bundle|bundle-hair|bundle-ground ref|masq|cluster|auto w4|w8|q8|o4 primary|shadow|diffuse "
                                              "[capsule|curve|thick|thick-curve] [masq|embree|embree1m] [width=256] [traces=4] [nearest|starts-last] [repeat=1]");
    const probe::Prims prims = argc > 5 ? probe::prims(argv[5]) : probe::Prims{};
    Scene scene = probe::scene(argv[1], prims);
    const Method method = probe::method(argv[2]);
    const NodeFormat nodes = probe::nodes(argv[3]);
    const RaySet set = probe::pick<RaySet>("ray set", argv[4],
                                    {{"primary", RaySet::Primary}, {"shadow", RaySet::Shadow}, {"diffuse", RaySet::Diffuse}});
    const bool curves = prims.curves;
    // embree: rtcIntersect1 / rtcOccluded1 per ray; embree1m: the stream API, with the
    // coherent hint on camera rays (the peers suite times both and keeps the faster).
    const int tracer = argc > 6 ? probe::pick<int>("tracer", argv[6], {{"masq", 0}, {"embree", 1}, {"embree1m", 2}}) : 0;
    const bool embree_side = tracer != 0;
    const EmbreeTrace how{tracer == 2 ? EmbreeApi::Stream : EmbreeApi::PerRay, tracer == 2 && set == RaySet::Primary};
    const int width = argc > 7 ? std::atoi(argv[7]) : 256;
    const int traces = argc > 8 ? std::atoi(argv[8]) : 4;
    const int repeat = argc > 10 ? std::atoi(argv[10]) : 1;
    if (width < 1 || traces < 1 || repeat < 1) throw std::invalid_argument("width, traces and repeat must be at least 1");
    BenchOptions opt;
    opt.backends = {"cpu"};
    opt.methods = {method};
    opt.ray_sets = {RaySet::Primary, set};
    opt.width = opt.height = width;
    opt.builders = {Builder::Sah4};
    opt.accel.builder.kind = Builder::Sah4;
    opt.node_formats = {nodes};
    opt.accel.nodes = nodes;
    if (curves) opt.accel.curve_isect = CurveIsect::Roving;
    if (argc > 9) opt.accel.blas_occlusion = parse_blas_occlusion(argv[9]);
    BuiltMethods built = build_methods(scene, opt);
    BackendPool pool;
    RayBatch b = make_ray_batches(scene, built, opt, pool).back();
    if (repeat > 1) {
      std::vector<kernel::Ray> repeated;
      repeated.reserve(b.rays.size() * std::size_t(repeat));
      for (const kernel::Ray& r : b.rays) repeated.insert(repeated.end(), std::size_t(repeat), r);
      b.rays = std::move(repeated);
    }
    const Query q = set == RaySet::Shadow ? Query::Any : Query::Closest;
    std::unique_ptr<Backend> be = make_backend("cpu");
    be->set_scene(built.scenes.at(method));
    std::vector<kernel::Hit> hits(b.rays.size());
    std::vector<kernel::RayStats> stats(b.rays.size());
    be->trace(b.rays, hits, stats, q);
    double tlas = 0, blas = 0, transforms = 0, calls = 0;
    for (const kernel::RayStats& s : stats) tlas += s.tlas_nodes, blas += s.blas_nodes, transforms += s.transforms, calls += s.isect_calls;
    std::unique_ptr<EmbreePeer> embree;
    if (embree_side) {
      // Embree's threads: the cpu backend's count (MASQ_CPU_THREADS, else every hardware
      // thread), so that the two sides' CPU times compare as the peers suite's do.
      const std::uint64_t threads = knob_integer(Knob::CpuThreads, "cpu").value_or(std::thread::hardware_concurrency());
      embree = std::make_unique<EmbreePeer>(int(std::clamp<std::uint64_t>(threads, 1, 1024)));
      embree->set_scene(scene, true);
    }
    std::vector<std::uint8_t> occluded(b.rays.size());
    Backend* masq_side = embree_side ? nullptr : be.get();
    // One warm-up trace first, outside probe_traces (not counted).
    if (embree_side && q == Query::Any) embree->occluded(b.rays, occluded, how);
    else if (embree_side) embree->trace(b.rays, hits, how);
    else be->trace(b.rays, hits, {}, q);
    const double cpu0 = process_cpu_seconds();
    const auto wall0 = std::chrono::steady_clock::now();
    probe_traces(masq_side, embree.get(), how, b, q, traces, hits, occluded);
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
    const double cpu = process_cpu_seconds() - cpu0;
    const double n = double(b.rays.size());
    std::printf("%s: %zu rays x %d traces counted (%zu rays); masq's counters per ray: tlas %.2f blas %.2f "
                "transforms %.2f isect %.2f\n",
                embree_side ? "embree" : "masq", b.rays.size(), traces, b.rays.size() * std::size_t(traces), tlas / n,
                blas / n, transforms / n, calls / n);
    std::printf("traces counted: %.1f ms wall, %.1f ms CPU time (every thread)\n", 1e3 * wall, 1e3 * cpu);
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "masq_trace_probe: %s\n", e.what());
    return 1;
  }
}
