// cpu bv tracer: the bv kernels compiled as C++, rays handed out to threads in chunks
// (host/cpu/trace_threads.h).
#include "host/bv_tracer.h"
#include "cpu/bv_units.h"
#include "host/cpu/cpu_units.h"
#include "host/cpu/trace_threads.h"
#include "host/scene_arrays.h"
#include "host/scene_variant.h"
#include "host/trace_faults.h"
#include "masq/error.h"
#include "masq/knobs.h"
#include <algorithm>
#include <chrono>
#include <climits>
#include <thread>

namespace masq {

namespace {

int bv_thread_count() {
  if (std::optional<std::uint64_t> n = knob_integer(Knob::CpuThreads, "cpu")) return int(std::min<std::uint64_t>(*n, INT_MAX));
  return int(std::max(1u, std::thread::hardware_concurrency()));
}

class CpuBvTracer final : public BvTracer {
 public:
  std::string name() const override { return "cpu"; }

  void set_scene(const BvScene& scene) override {
    auto t0 = std::chrono::steady_clock::now();
    scene_ = scene; // own a copy: the caller's may go away
    kd_ = kernel_data(scene_array_data(scene_));
    have_scene_ = true;
    timing_.scene_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  }

  void trace(std::span<const kernel::Ray> rays, std::span<kernel::Hit> hits,
             std::span<kernel::RayStats> stats) override {
    if (!have_scene_) throw Error("cpu bv: trace called before set_scene");
    if (hits.size() != rays.size() || (!stats.empty() && stats.size() != rays.size()))
      throw Error("cpu bv: hits/stats spans must have one entry per ray");
    if (rays.size() > std::size_t(INT32_MAX)) throw Error("cpu bv: more than 2^31-1 rays in one batch");
    // Robust intersectors only, as on the other backends (bv_unit.inc).
    KernelFeatures features = scene_.prims.features;
    features.mode = Mode::Robust;
    const KernelVariant variant = kernel_variant(features, {!stats.empty(), false});
    const int bv_type = bv_type_kernel_id(scene_.type);
    const cpu::UnitFn fn = cpu::find_unit(cpu::kBvUnits, "bv", [&](std::string_view key) {
      return key == "bv_type" ? bv_type : switch_value(variant, key);
    });
    const int n = int(rays.size());
    const int nodes = int(scene_.node_count());
    const std::int32_t budget = step_budget(scene_.node_count());
    auto t0 = std::chrono::steady_clock::now();
    threads_.for_chunks(n, 256, [&](int begin, int end) {
      fn(kd_, variant, rays.data(), hits.data(), stats.empty() ? nullptr : stats.data(), begin, end, nodes, budget);
    });
    timing_.trace_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    timing_.wall_seconds = timing_.trace_seconds; // traced in place: no upload or readback
    check_trace_faults("cpu bv", "host", hits, budget);
  }

  TraceTiming timing() const override { return timing_; }

 private:
  cpu::TraceThreads threads_{bv_thread_count()};
  BvScene scene_;
  kernel::KernelData kd_{};
  bool have_scene_ = false;
  TraceTiming timing_;
};

} // namespace

std::unique_ptr<BvTracer> make_cpu_bv_tracer() { return std::make_unique<CpuBvTracer>(); }

} // namespace masq
