// "rayquery" backend: the driver's own acceleration structures (host/vulkan/driver_scene.h)
// traversed with VK_KHR_ray_query from a compute shader (kernels/rayquery.comp) that calls
// the shared intersector on every procedural candidate.
#include "host/vulkan/vk_clock.h"
#include "host/device_fill.h"
#include "host/scene_variant.h"
#include "host/vulkan/driver_scene.h"
#include "host/vulkan/trace_dispatch.h"
#include "host/vulkan/vk_lanes.h"
#include "host/vulkan/vk_shader_limits.h"
#include "host/vulkan/vulkan_backends.h"
#include "kernels/kernel_data.h"
#include "spirv/rayquery_comp_addr_spv.h"
#include "spirv/rayquery_comp_spv.h"
#include <chrono>

namespace masq {
namespace {

using vk::Clock;
using vk::seconds_since;

const char* const kRayQueryName = "rayquery";

class RayQueryBackend final : public Backend {
 public:
  RayQueryBackend()
      : ctx_(vk::Context::get(kRayQueryName, DeviceNeed::RayQuery)),
        layout_(*ctx_, descriptor_types(), sizeof(kernel::TraceParams)), batch_(*ctx_) {}

  std::string name() const override { return kRayQueryName; }
  std::string device_name() const override { return ctx_->device_name(); }

  void set_scene(const PackedScene& scene) override {
    auto t0 = Clock::now();
    have_scene_ = false;
    features_ = driver_.set(scene);
    have_scene_ = true;
    timing_.scene_seconds = seconds_since(t0);
  }

  void trace(std::span<const kernel::Ray> rays, std::span<kernel::Hit> hits, std::span<kernel::RayStats> stats,
             Query query) override {
    if (!have_scene_) throw Error("rayquery: trace called before set_scene");
    driver_.widen_for(rays);
    VkPipeline p = pipeline(!stats.empty(), query == Query::Any);
    batch_.run(kRayQueryName, layout_, p, vk::local_size(*ctx_), static_cast<std::int32_t>(driver_.part_count()), rays, hits,
               stats)
        .into(timing_);
  }

  TraceTiming timing() const override { return timing_; }
  std::size_t fill_rays() const override { return fill_rays_for(vk::resident_threads(*ctx_)); }

  // The driver's structures count with their sizes on the device (BLAS compacted, vk::build_accels).
  std::size_t device_bytes() const override { return driver_.device_bytes(); }

 private:
  static std::vector<VkDescriptorType> descriptor_types() { return vk::kernel_descriptor_types(); }

  VkPipeline pipeline(bool stats, bool any_hit) {
    vk::PipelineVariants& variants = driver_.addressed() ? addressed_ : bound_;
    const std::vector<std::uint32_t> spec =
        vk::spec_constants(kernel_variant(features_, {stats, any_hit}), vk::local_size(*ctx_));
    const vk::PipelineVariants::Variant& v = variants.get(spec, [&](VkPipeline p) {
      // An empty dispatch (ray_count 0) triggers the driver's JIT.
      batch_.bind_minimal(layout_);
      kernel::TraceParams pc{0, 0, 0, 0};
      layout_.dispatch(p, &pc, 1);
    });
    timing_.compile_seconds = v.compile_seconds;
    return v.pipeline.get();
  }

  std::shared_ptr<vk::Context> ctx_;
  vk::KernelLayout layout_;
  vk::PipelineVariants bound_{layout_, rayquery_comp_spv}; // after layout_: destroyed first
  vk::PipelineVariants addressed_{layout_, rayquery_comp_addr_spv};
  vk::RayBatch batch_;
  vk::DriverScene driver_{*ctx_, layout_, kRayQueryName};
  KernelFeatures features_;
  bool have_scene_ = false;
  TraceTiming timing_;
};

} // namespace

std::unique_ptr<Backend> make_rayquery_backend() { return std::make_unique<RayQueryBackend>(); }

} // namespace masq
