// vulkan bv tracer: kernels/trace_bv.comp, one SPIR-V module per node type (and per
// array access: bound, or by address for scenes over one storage binding), the other
// switches as specialization constants (host/vulkan/trace_dispatch.h). The arrays are
// the rows of kernels/scene_array_table.h the bv kernels read.
#include "host/bv_tracer.h"
#include "host/vulkan/trace_dispatch.h"
#include "host/scene_variant.h"
#include "host/trace_faults.h"
#include "host/vulkan/vk_shader_limits.h"
#include "kernels/kernel_data.h"
#include "masq/error.h"
#include "spirv/trace_bv_modules.h"
#include <chrono>
#include <map>
#include <tuple>
#include <memory>
#include <utility>

namespace masq {
namespace {

using Clock = std::chrono::steady_clock;
const char* const kVulkanBvName = "vulkan";

class VulkanBvTracer final : public BvTracer {
 public:
  VulkanBvTracer()
      : ctx_(vk::Context::get(kVulkanBvName)),
        layout_(*ctx_, vk::kernel_descriptor_types(), sizeof(kernel::TraceParams)),
        batch_(*ctx_) {}

  std::string name() const override { return kVulkanBvName; }

  void set_scene(const BvScene& scene) override {
    auto t0 = Clock::now();
    if (scene.node_count() > std::size_t(INT32_MAX)) throw Error("vulkan bv: more than 2^31-1 nodes");
    scene_ = vk::SceneBuffers{};
    vk::add_scene_arrays(scene_, *ctx_, kVulkanBvName, scene_array_data(scene), KernelFamily::Bv);
    scene_.finish(*ctx_, kVulkanBvName);
    scene_.bind(layout_);
    type_ = scene.type;
    node_count_ = int(scene.node_count());
    features_ = scene.prims.features;
    features_.mode = Mode::Robust; // the bv kernels use the robust intersectors
    have_scene_ = true;
    timing_.scene_seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  }

  void trace(std::span<const kernel::Ray> rays, std::span<kernel::Hit> hits,
             std::span<kernel::RayStats> stats) override {
    if (!have_scene_) throw Error("vulkan bv: trace called before set_scene");
    VkPipeline p = pipeline(!stats.empty());
    const std::int32_t budget = step_budget(std::size_t(node_count_));
    batch_.run(kVulkanBvName, layout_, p, vk::local_size(*ctx_), node_count_, rays, hits, stats, budget).into(timing_);
    check_trace_faults("vulkan bv", ctx_->device_name(), hits, budget);
  }

  TraceTiming timing() const override { return timing_; }

 private:
  // The pipelines of the scene's volume type and array access, made on first use.
  vk::PipelineVariants& variants() {
    const int type = bv_type_kernel_id(type_);
    const bool addressed = scene_.addressed();
    const bool sized = kernel_knobs().stack_sized; // the MASQ_STACK_SIZED row's module (kernels/variants.h)
    std::unique_ptr<vk::PipelineVariants>& v = variants_[{type, addressed, sized}];
    if (!v)
      for (const vk::TraceBvModule& m : vk::kTraceBvModules)
        if (m.bv_type == type)
          v = std::make_unique<vk::PipelineVariants>(
              layout_, sized ? (addressed ? m.sized_addressed : m.sized_bound) : (addressed ? m.addressed : m.bound));
    if (!v) throw Error("vulkan bv: no SPIR-V module for bounding-volume type " + std::to_string(type));
    return *v;
  }

  VkPipeline pipeline(bool stats) {
    const std::vector<std::uint32_t> spec =
        vk::spec_constants(kernel_variant(features_, {stats, false}), vk::local_size(*ctx_));
    const vk::PipelineVariants::Variant& v = variants().get(spec, [&](VkPipeline p) {
      batch_.bind_minimal(layout_); // an empty dispatch triggers the driver's JIT
      kernel::TraceParams pc{0, node_count_, 0, step_budget(std::size_t(node_count_))};
      layout_.dispatch(p, &pc, 1);
    });
    timing_.compile_seconds = v.compile_seconds;
    return v.pipeline.get();
  }

  std::shared_ptr<vk::Context> ctx_;
  vk::KernelLayout layout_;
  // By (type, addressed, stacks sized); after layout_: destroyed first.
  std::map<std::tuple<int, bool, bool>, std::unique_ptr<vk::PipelineVariants>> variants_;
  vk::RayBatch batch_;
  vk::SceneBuffers scene_;
  BvType type_ = BvType::Scb;
  int node_count_ = 0;
  KernelFeatures features_;
  bool have_scene_ = false;
  TraceTiming timing_;
};

} // namespace

std::unique_ptr<BvTracer> make_vulkan_bv_tracer() { return std::make_unique<VulkanBvTracer>(); }

} // namespace masq
