// "vulkan" backend: the shared two-level traversal (kernels/trace.comp) as a compute
// shader. One pipeline per variant (stats, triangles, capsules), created on first use
// and cached; the first dispatch of each is part of its compile time, because lavapipe
// JIT-compiles there. Where the device has bufferDeviceAddress the addressed module
// (trace_comp_addr_spv; see SceneBuffers) runs; otherwise the bound one, and scenes with
// an array over one storage binding are refused. Each in two stack forms (MASQ_STACK_FORM,
// kernels/variants.h): trace_comp*_spv with fixed stacks, trace_comp_sized*_spv sized by
// the specialization constants.
#include "host/vulkan/vk_clock.h"
#include "host/device_fill.h"
#include "host/limit_knob.h"
#include "host/vulkan/trace_dispatch.h"
#include "host/vulkan/vk_lanes.h"
#include "host/vulkan/vulkan_backends.h"
#include "host/scene_variant.h"
#include "host/trace_faults.h"
#include "host/vulkan/vk_shader_limits.h"
#include "kernels/kernel_data.h"
#include "spirv/trace_comp_addr_spv.h"
#include "spirv/trace_comp_sized_addr_spv.h"
#include "spirv/trace_comp_sized_spv.h"
#include "spirv/trace_comp_spv.h"
#include <chrono>
#include <cstdlib>
#include <map>
#include <mutex>
#include <tuple>

namespace masq {
namespace {

using vk::Clock;
using vk::seconds_since;

const char* const kVulkanName = "vulkan";

// How the kernel reads the scene arrays: "addressed" (buffer device address) whenever
// the device supports it, or "bound" (storage-buffer descriptors) except for arrays over
// one binding. Default addressed: on lavapipe it traced 1.3-1.7x faster than bound in
// interleaved runs (bench/addressed_cost.cpp; docs/results.md), as llvmpipe
// bounds-checks every descriptor access. MASQ_VK_ADDRESSING=bound|addressed picks.
bool prefer_addressed() { return choice_knob("vulkan", Knob::VkAddressing, "addressed"); }

class VulkanComputeBackend final : public Backend {
 public:
  VulkanComputeBackend()
      : ctx_(vk::Context::get(kVulkanName)),
        layout_(*ctx_, vk::kernel_descriptor_types(), sizeof(kernel::TraceParams)),
        batch_(*ctx_) {}


  std::string name() const override { return kVulkanName; }
  std::string device_name() const override { return ctx_->device_name(); }

  void set_scene(const PackedScene& scene) override {
    auto t0 = Clock::now();
    scene_ = vk::SceneBuffers{}; // release the old scene first (memory)
    vk::add_scene_arrays(scene_, *ctx_, kVulkanName, scene_array_data(scene), KernelFamily::TwoLevel);
    scene_.finish(*ctx_, kVulkanName, prefer_addressed());
    scene_.bind(layout_);
    tlas_root_ = scene.tlas_root;
    budget_ = step_budget(scene.node_count());
    features_ = scene.features;
    have_scene_ = true;
    timing_.scene_seconds = seconds_since(t0);
  }

  void trace(std::span<const kernel::Ray> rays, std::span<kernel::Hit> hits, std::span<kernel::RayStats> stats,
             Query query) override {
    if (!have_scene_) throw Error("vulkan: trace called before set_scene");
    VkPipeline p = pipeline(!stats.empty(), query == Query::Any);
    batch_.run(kVulkanName, layout_, p, vk::local_size(*ctx_), tlas_root_, rays, hits, stats, budget_).into(timing_);
    check_trace_faults(kVulkanName, ctx_->device_name(), hits, budget_);
  }

  TraceTiming timing() const override { return timing_; }
  std::size_t fill_rays() const override { return fill_rays_for(vk::resident_threads(*ctx_)); }
  std::size_t device_bytes() const override { return scene_.bytes; }

 private:
  VkPipeline pipeline(bool stats, bool any_hit) {
    const KernelVariant kv = kernel_variant(features_, {stats, any_hit});
    // The module of the variant's stack form (MASQ_STACK_SIZED, kernels/variants.h) and
    // array access; the other switches are specialization constants.
    vk::PipelineVariants& variants = kv.stack_sized ? (scene_.addressed() ? sized_addressed_ : sized_bound_)
                                                    : (scene_.addressed() ? addressed_ : bound_);
    const std::vector<std::uint32_t> spec = vk::spec_constants(kv, vk::local_size(*ctx_));
    const vk::PipelineVariants::Variant& v = variants.get(spec, [&](VkPipeline p) {
      // An empty dispatch (ray_count 0) triggers the driver's JIT.
      batch_.bind_minimal(layout_);
      kernel::TraceParams pc{0, tlas_root_, 0, budget_};
      layout_.dispatch(p, &pc, 1);
    });
    timing_.compile_seconds = v.compile_seconds;
    return v.pipeline.get();
  }

  std::shared_ptr<vk::Context> ctx_;
  vk::KernelLayout layout_;
  vk::PipelineVariants bound_{layout_, trace_comp_spv}; // after layout_: destroyed first
  vk::PipelineVariants addressed_{layout_, trace_comp_addr_spv};
  vk::PipelineVariants sized_bound_{layout_, trace_comp_sized_spv};
  vk::PipelineVariants sized_addressed_{layout_, trace_comp_sized_addr_spv};
  vk::RayBatch batch_;
  vk::SceneBuffers scene_;
  std::int32_t tlas_root_ = -1;
  std::int32_t budget_ = 1; // kernel::TraceParams::step_budget (host/trace_faults.h)
  KernelFeatures features_;
  bool have_scene_ = false;
  TraceTiming timing_;
};

} // namespace

std::unique_ptr<Backend> make_vulkan_backend() { return std::make_unique<VulkanComputeBackend>(); }

} // namespace masq
