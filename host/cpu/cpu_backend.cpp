#include "host/cpu/cpu_backend.h"
#include "cpu/trace_units.h"
#include "host/cpu/cpu_units.h"
#include "host/cpu/entry_curves.h"
#include "host/cpu/leaf_capsules.h"
#include "host/cpu/trace_threads.h"
#include "host/device_fill.h"
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

int thread_count() {
  if (std::optional<std::uint64_t> n = knob_integer(Knob::CpuThreads, "cpu")) return int(std::min<std::uint64_t>(*n, INT_MAX));
  return std::max(1u, std::thread::hardware_concurrency());
}

class CpuBackend final : public Backend {
 public:
  std::string name() const override { return "cpu"; }
  std::string device_name() const override {
    return "kernel source as C++, " + std::to_string(threads_.count()) + " threads";
  }

  void set_scene(const PackedScene& scene) override {
    auto start = std::chrono::steady_clock::now();
    scene_ = scene; // own a copy: the caller's scene may go away
    leaf_capsules(scene_, leaf_capsules_);
    kd_ = kernel_data(scene_array_data(scene_));
    kd_.leaf_capsule_rows = leaf_capsules_.rows.data();
    kd_.leaf_capsule_stride = leaf_capsules_.stride;
    entry_curves(scene_, entry_curves_);
    kd_.entry_curves = entry_curves_.empty() ? nullptr : &entry_curves_.front().curve;
    kd_.entry_packets = entry_packets(scene_) ? 1 : 0;
    timing_.scene_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    has_scene_ = true;
  }

  void trace(std::span<const kernel::Ray> rays, std::span<kernel::Hit> hits, std::span<kernel::RayStats> stats,
             Query query) override {
    if (!has_scene_) throw Error("cpu: trace called before set_scene");
    if (hits.size() != rays.size() || (!stats.empty() && stats.size() != rays.size()))
      throw Error("cpu: hits/stats spans must have one entry per ray");
    if (rays.size() > std::size_t(INT32_MAX)) throw Error("cpu: more than 2^31-1 rays in one batch");
    const KernelVariant variant = kernel_variant(scene_.features, {!stats.empty(), query == Query::Any});
    const cpu::UnitFn fn = cpu::find_unit(cpu::kTraceUnits, "trace",
                                          [&](std::string_view key) { return switch_value(variant, key); });
    const int n = int(rays.size());
    const std::int32_t budget = step_budget(scene_.node_count());
    auto start = std::chrono::steady_clock::now();
    threads_.for_chunks(n, kChunk, [&](int begin, int end) {
      fn(kd_, variant, rays.data(), hits.data(), stats.empty() ? nullptr : stats.data(), begin, end, scene_.tlas_root,
         budget);
    });
    timing_.trace_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    timing_.wall_seconds = timing_.trace_seconds; // traced in place: no upload or readback
    check_trace_faults("cpu", device_name(), hits, budget);
  }

  TraceTiming timing() const override { return timing_; }
  std::size_t device_bytes() const override {
    return scene_.acceleration_bytes() + scene_.primitive_bytes() + leaf_capsules_.rows.size() * sizeof(float) +
           entry_curves_.size() * sizeof(EntryCurve);
  }
  // Each thread takes kChunk rays at a time (trace above).
  std::size_t fill_rays() const override { return fill_rays_for(std::size_t(threads_.count()) * kChunk); }

 private:
  static constexpr int kChunk = 256; // small chunks, handed out as threads free up, balance uneven rays
  cpu::TraceThreads threads_{thread_count()};
  PackedScene scene_;
  LeafCapsuleRows leaf_capsules_; // kd_.leaf_capsule_rows
  HugePageVector<EntryCurve> entry_curves_; // kd_.entry_curves
  kernel::KernelData kd_{};
  bool has_scene_ = false;
  TraceTiming timing_;
};

} // namespace

std::unique_ptr<Backend> make_cpu_backend() { return std::make_unique<CpuBackend>(); }

} // namespace masq
