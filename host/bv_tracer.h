// Tracing a binary bounding-volume hierarchy (bvh/bv/bv_scene.h) with the bv kernels
// (kernels/bv_traverse.h), on the cpu, vulkan and opencl backends. A separate entry
// point from Backend: the scene is one world-space hierarchy (no TLAS, no instances),
// and each BV type is its own compiled kernel variant. Counters per ray in RayStats:
// blas_nodes = N_b (ray/volume tests), isect_calls = N_t (ray/primitive tests),
// tlas_nodes = nodes visited.
#pragma once
#include "bvh/bv/bv_scene.h"
#include "host/backend.h"
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace masq {

class BvTracer {
 public:
  virtual ~BvTracer() = default;
  virtual std::string name() const = 0;
  virtual void set_scene(const BvScene& scene) = 0; // replaces any previous one
  // Closest hit per ray; stats empty: the counter-free variant, else one per ray.
  virtual void trace(std::span<const kernel::Ray> rays, std::span<kernel::Hit> hits,
                     std::span<kernel::RayStats> stats) = 0;
  virtual TraceTiming timing() const = 0;
};

const std::vector<std::string>& bv_backend_names(); // the registry's backends with a bv tracer
// Throws BackendUnavailable (one line) when the backend cannot run here, masq::Error
// for a name that is not a bv backend.
std::unique_ptr<BvTracer> make_bv_tracer(std::string_view backend);

std::unique_ptr<BvTracer> make_cpu_bv_tracer();
std::unique_ptr<BvTracer> make_vulkan_bv_tracer();
std::unique_ptr<BvTracer> make_opencl_bv_tracer();

} // namespace masq
