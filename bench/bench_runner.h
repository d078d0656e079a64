// Measures one scene through every backend x method with the same rays: device time
// after warm-up, median and min-max over repetitions, counters per ray, memory. Each
// ray set (primary, shadow, diffuse) is measured separately with the same rays on
// every backend and method. On one backend the methods' timed traces take turns, round
// by round (each method's structure stays uploaded in its own backend slot), so a load
// that comes and goes on a shared machine falls on all of them alike.
#pragma once
#include "bench/auto_pilot.h"
#include "bench/backend_pool.h"
#include "bench/ray_sets.h"
#include "bvh/twolevel/build_accel.h"
#include "bvh/packed_scene.h"
#include "host/backend.h"
#include "scenes/scene.h"
#include <array>
#include <functional>
#include <map>
#include <span>
#include <string>
#include <vector>

namespace masq {

// How the bench's auto rows keep a candidate: Pilot: per backend and ray set, the one
// that traces a sample of those rays fastest on that backend (bench/auto_pilot.h); Model:
// the structure cost model's choice (bvh/twolevel/build_accel.h), as masq render and the library
// make it.
enum class AutoBy { Pilot, Model };
inline constexpr NameRow<AutoBy> auto_by_rows[] = {
    {AutoBy::Pilot, "pilot",
     "trace a sample of each ray set through each candidate on the backend measured, keep the fastest"},
    {AutoBy::Model, "model", "the cost model's choice, as masq render makes it"},
};
inline constexpr NameTable auto_by_table{"auto choice", auto_by_rows};
inline const char* auto_by_name(AutoBy a) { return auto_by_table.name(a); }
inline AutoBy parse_auto_by(std::string_view name) { return auto_by_table.parse(name); } // throws masq::Error

struct BenchOptions {
  std::vector<std::string> backends = backend_names();
  std::vector<Method> methods = {Method::Ref, Method::Masq, Method::Cluster, Method::Auto};
  std::vector<RaySet> ray_sets = {RaySet::Primary, RaySet::Shadow, RaySet::Diffuse};
  int width = 512;
  int height = 512;
  int warmup = 1;
  int repetitions = 5;
  // Each timed sample traces a ray set over and over until it has traced at least this
  // many rays, and counts the time per trace (0: once). The hair's shadow and diffuse
  // sets at a pilot's resolution hold a few hundred to a few thousand rays, a trace of
  // about a millisecond: once, its time measures the threads' wake-up as much as tracing.
  std::size_t sample_rays = 0;
  bool keep_per_ray = false; // keep every row's hits and counters (heatmaps, agreement)
  // Shadow rays ask the occlusion question (any hit, early exit), as a renderer would;
  // false traces them for the closest hit like the other sets.
  bool shadow_any_hit = true;
  AccelOptions accel;        // mode, curve OBB, phantom iterations, builder options
  // Binary BVH builders run side by side (each replaces accel.builder.kind in turn);
  // the rays are the same for all.
  std::vector<Builder> builders = {Builder::Sah};
  // Node formats run side by side the same way (each replaces accel.nodes in turn).
  std::vector<NodeFormat> node_formats = {NodeFormat::W4};
  // Curve intersectors run side by side the same way (each replaces accel.curve_isect).
  std::vector<CurveIsect> curve_isects = {CurveIsect::Phantom};
  AutoBy auto_by = AutoBy::Pilot;
  PilotOptions pilot;
  std::function<void(const std::string&)> progress; // one line per step, may be empty
  void say(const std::string& line) const {
    if (progress) progress(line);
  }
};

struct BenchRow {
  std::string backend;
  std::string device;
  Method method = Method::Ref;
  Builder builder = Builder::Sah;
  NodeFormat nodes = NodeFormat::W4;
  CurveIsect curve_isect = CurveIsect::Phantom;
  BlasOcclusion blas_occlusion = BlasOcclusion::Nearest; // the structure's (occlusion queries' BLAS order)
  RaySet ray_set = RaySet::Primary;
  Query query = Query::Closest;
  std::string unavailable; // non-empty: the backend could not run (why)
  double rays = 0;
  double median_s = 0, min_s = 0, max_s = 0; // device time of the timed traces
  // Medians over the timed traces of the host-clock times (host/backend.h TraceTiming):
  // the whole trace, and the parts writing rays and reading results back.
  double wall_s = 0, upload_s = 0, readback_s = 0;
  // Median over the timed samples of the process's CPU time per trace, every thread
  // (CLOCK_PROCESS_CPUTIME_ID): the peers suite's deciding figure on a shared machine.
  double cpu_s = 0;
  std::size_t fill_rays = 0; // rays that fill the row's device (Backend::fill_rays; 0: unknown)
  double build_s = 0, scene_s = 0, compile_s = 0;
  // Per ray, from the stats variant (rayquery, rtpipeline: node tests and transforms are not observable: -1).
  double tlas_nodes = 0, blas_nodes = 0, transforms = 0, isect_calls = 0;
  double hit_fraction = 0;
  std::size_t accel_bytes = 0, prim_bytes = 0, device_bytes = 0;
  std::size_t primitives = 0;
  BuildStats build;
  // The GPU kernels' (vulkan, opencl) traversal stacks for this structure, in entries
  // (host/stack_size.h); the cpu keeps 64, rayquery and rtpipeline have none.
  std::int32_t tlas_stack = 0, blas_stack = 0;
  // auto by pilot: each candidate's fastest pilot trace (s), indexed by Method like
  // build.auto_candidates (0: not a candidate); the sample's size; the pilot's wall time.
  std::array<double, 4> pilot_seconds{};
  bool pilot_mix_is_ref = false; // the mix was ref's structure: not traced, ref's time
  std::size_t pilot_rays = 0;
  double pilot_s = 0;
  std::vector<kernel::Hit> hits;        // keep_per_ray only
  std::vector<kernel::RayStats> stats;  // keep_per_ray only
  double mrays_per_s() const { return median_s > 0 ? rays / median_s * 1e-6 : 0; }
};

// Traces of a set of `rays` rays that make one timed sample of at least `sample_rays`
// rays (BenchOptions::sample_rays): 1 when the set alone has that many (or is empty).
int traces_per_sample(std::size_t rays, std::size_t sample_rays);

// The scene built once per method (host BVH build time is in each PackedScene's stats).
struct BuiltMethods {
  std::map<Method, PackedScene> scenes; // auto: the model's choice
  AutoCandidates auto_candidates;       // auto by pilot: all of its candidates (else empty)
};
BuiltMethods build_methods(const Scene& scene, const BenchOptions& opt);

struct RayBatch {
  RaySet set = RaySet::Primary;
  std::vector<kernel::Ray> rays;
};

// Camera rays of opt.width x opt.height and the secondary sets of opt.ray_sets, derived
// from the primary hits on the first backend of `opt` that runs (ref method when built).
std::vector<RayBatch> make_ray_batches(const Scene& scene, const BuiltMethods& built,
                                       const BenchOptions& opt, BackendPool& pool);

// A bench run with what it traced kept: the structures of every builder x node format
// (in opt's order, each with the options it was built with), the ray batches, the rows.
struct BenchRun {
  std::vector<BuiltMethods> built;
  std::vector<BenchOptions> options;
  std::vector<RayBatch> batches;
  std::vector<BenchRow> rows;
  // The structures `row` traced (its builder and node format); throws if not built.
  const BuiltMethods& built_for(const BenchRow& row) const;
};

// Everything: build, camera rays of opt.width x opt.height, each ray set of opt, for
// each builder of opt.builders and node format of opt.node_formats. Rows: backend, then
// method, then builder, then node format, then set. Every backend x method (each
// method's scene uploaded once per backend, into its own slot; auto by pilot once per
// ray set); backends come from `pool`.
BenchRun run_bench_kept(const Scene& scene, const BenchOptions& opt, BackendPool& pool);
std::vector<BenchRow> run_bench(const Scene& scene, const BenchOptions& opt, BackendPool& pool);
std::vector<BenchRow> run_bench(const Scene& scene, const BenchOptions& opt);

} // namespace masq
