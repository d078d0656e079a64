#include "host/cpu/cpu_backend.h"
#include "host/cpu/cpu_kernels.h"
#include "kernels/variants.h"
#include "scenes/error.h"
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdlib>
#include <thread>

namespace masq {

namespace {

int thread_count() {
  if (const char* env = std::getenv("MASQ_CPU_THREADS")) {
    int n = std::atoi(env);
    if (n > 0) return n;
  }
  return std::max(1u, std::thread::hardware_concurrency());
}

class CpuBackend final : public Backend {
 public:
  std::string name() const override { return "cpu"; }
  std::string device_name() const override {
    return "kernel source as C++, " + std::to_string(threads_) + " threads";
  }

  void set_scene(const PackedScene& scene) override {
    auto start = std::chrono::steady_clock::now();
    scene_ = scene; // own a copy: the caller's scene may go away
    kd_.nodes = scene_.nodes.data();
    kd_.node_words = static_cast<const std::uint32_t*>(scene_.node_data()); // w8, q8
    kd_.refs = scene_.refs.data();
    kd_.instances = scene_.instances.data();
    kd_.masq_instances = scene_.masq_instances.data();
    kd_.masq_owners = scene_.masq_owners.data();
    kd_.frames = scene_.frames.data();
    kd_.geoms = scene_.geoms.data();
    kd_.triangles = scene_.triangles.data();
    kd_.capsules = scene_.capsules.data();
    kd_.cones = scene_.cones.data();
    kd_.spheres = scene_.spheres.data();
    kd_.curves = scene_.curves.data();
    timing_.scene_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    has_scene_ = true;
  }

  void trace(std::span<const kernel::Ray> rays, std::span<kernel::Hit> hits, std::span<kernel::RayStats> stats,
             Query query) override {
    if (!has_scene_) throw Error("cpu: trace called before set_scene");
    if (hits.size() != rays.size() || (!stats.empty() && stats.size() != rays.size()))
      throw Error("cpu: hits/stats spans must have one entry per ray");
    if (rays.size() > std::size_t(INT32_MAX)) throw Error("cpu: more than 2^31-1 rays in one batch");
    const bool robust = scene_.features.mode == Mode::Robust;
    cpu::TraceRangeFn fn = robust ? cpu::trace_range_stats_robust : cpu::trace_range_stats_fast;
    if (stats.empty()) {
      switch (scene_.features.nodes) {
        case NodeFormat::W4: fn = robust ? cpu::trace_range_plain_robust : cpu::trace_range_plain_fast; break;
        case NodeFormat::W8: fn = robust ? cpu::trace_range_plain_robust_w8 : cpu::trace_range_plain_fast_w8; break;
        case NodeFormat::Q8: fn = robust ? cpu::trace_range_plain_robust_q8 : cpu::trace_range_plain_fast_q8; break;
      }
    }
    const int curve_iters = scene_.features.curve_iters;
    const int n = int(rays.size());
    // Small chunks handed out dynamically balance uneven rays across threads.
    const int chunk = 256;
    std::atomic<int> next{0};
    const bool any_hit = query == Query::Any;
    const bool single_blas = scene_.features.single_blas;
    const int node_format = node_format_id(scene_.features.nodes);
    auto worker = [&] {
      kernel::curve_iters_runtime = curve_iters; // per thread (see kernels/variants.h)
      kernel::any_hit_runtime = any_hit;
      kernel::single_blas_runtime = single_blas;
      kernel::node_format_runtime = node_format;
      for (int b = next.fetch_add(chunk); b < n; b = next.fetch_add(chunk))
        fn(kd_, rays.data(), hits.data(), stats.empty() ? nullptr : stats.data(), b, std::min(n, b + chunk),
           scene_.tlas_root);
    };
    auto start = std::chrono::steady_clock::now();
    std::vector<std::thread> pool;
    for (int t = 1; t < threads_; ++t) pool.emplace_back(worker);
    worker();
    for (std::thread& t : pool) t.join();
    timing_.trace_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }

  TraceTiming timing() const override { return timing_; }
  std::size_t device_bytes() const override { return scene_.acceleration_bytes() + scene_.primitive_bytes(); }

 private:
  int threads_ = thread_count();
  PackedScene scene_;
  kernel::KernelData kd_{};
  bool has_scene_ = false;
  TraceTiming timing_;
};

} // namespace

std::unique_ptr<Backend> make_cpu_backend() { return std::make_unique<CpuBackend>(); }

} // namespace masq
