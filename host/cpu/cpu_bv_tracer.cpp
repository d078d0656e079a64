// cpu bv tracer: the bv kernels compiled as C++, rays handed out to threads in chunks.
#include "host/bv_tracer.h"
#include "host/cpu/cpu_bv_kernels.h"
#include "scenes/error.h"
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdlib>
#include <thread>

namespace masq {

namespace {

int bv_thread_count() {
  if (const char* env = std::getenv("MASQ_CPU_THREADS")) {
    int n = std::atoi(env);
    if (n > 0) return n;
  }
  return int(std::max(1u, std::thread::hardware_concurrency()));
}

class CpuBvTracer final : public BvTracer {
 public:
  std::string name() const override { return "cpu"; }

  void set_scene(const BvScene& scene) override {
    auto t0 = std::chrono::steady_clock::now();
    scene_ = scene; // own a copy: the caller's may go away
    const PackedScene& p = scene_.prims;
    kd_ = kernel::KernelData{};
    kd_.frames = p.frames.data();
    kd_.geoms = p.geoms.data();
    kd_.triangles = p.triangles.data();
    kd_.capsules = p.capsules.data();
    kd_.cones = p.cones.data();
    kd_.spheres = p.spheres.data();
    kd_.curves = p.curves.data();
    kd_.bv_aabb = scene_.aabb.data();
    kd_.bv_sphere = scene_.sphere.data();
    kd_.bv_obb = scene_.obb.data();
    kd_.bv_scb = scene_.scb.data();
    kd_.bv_prims = scene_.refs.data();
    have_scene_ = true;
    timing_.scene_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  }

  void trace(std::span<const kernel::Ray> rays, std::span<kernel::Hit> hits,
             std::span<kernel::RayStats> stats) override {
    if (!have_scene_) throw Error("cpu bv: trace called before set_scene");
    if (hits.size() != rays.size() || (!stats.empty() && stats.size() != rays.size()))
      throw Error("cpu bv: hits/stats spans must have one entry per ray");
    if (rays.size() > std::size_t(INT32_MAX)) throw Error("cpu bv: more than 2^31-1 rays in one batch");
    cpu::BvRangeFn fn = pick(!stats.empty());
    const int n = int(rays.size());
    const int nodes = int(scene_.node_count());
    const int chunk = 256;
    std::atomic<int> next{0};
    auto worker = [&] {
      for (int b = next.fetch_add(chunk); b < n; b = next.fetch_add(chunk))
        fn(kd_, rays.data(), hits.data(), stats.empty() ? nullptr : stats.data(), b, std::min(n, b + chunk), nodes);
    };
    auto t0 = std::chrono::steady_clock::now();
    std::vector<std::thread> pool;
    for (int t = 1; t < threads_; ++t) pool.emplace_back(worker);
    worker();
    for (std::thread& t : pool) t.join();
    timing_.trace_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  }

  TraceTiming timing() const override { return timing_; }

 private:
  cpu::BvRangeFn pick(bool stats) const {
    switch (scene_.type) {
      case BvType::Aabb: return stats ? cpu::trace_bv_aabb_stats : cpu::trace_bv_aabb_plain;
      case BvType::Sphere: return stats ? cpu::trace_bv_sphere_stats : cpu::trace_bv_sphere_plain;
      case BvType::Obb: return stats ? cpu::trace_bv_obb_stats : cpu::trace_bv_obb_plain;
      case BvType::Scb: return stats ? cpu::trace_bv_scb_stats : cpu::trace_bv_scb_plain;
    }
    throw Error("cpu bv: unknown bounding-volume type");
  }

  int threads_ = bv_thread_count();
  BvScene scene_;
  kernel::KernelData kd_{};
  bool have_scene_ = false;
  TraceTiming timing_;
};

} // namespace

std::unique_ptr<BvTracer> make_cpu_bv_tracer() { return std::make_unique<CpuBvTracer>(); }

} // namespace masq
