// "rtpipeline" backend: the driver's own acceleration structures (host/vulkan/driver_scene.h,
// the same as rayquery's) traversed by VK_KHR_ray_tracing_pipeline, which calls masq's
// intersectors as intersection shaders through the shader binding table
// (host/vulkan/rt_pipeline.h, kernels/rt_shared.h): the mechanism of the masquerade
// paper's OptiX programs. It also runs where ray query does not, such as NVIDIA GPUs
// without RT cores, so it is the driver-traversal check there.
// Each batch of rays is one command buffer: the counters zeroed (stats variant), then
// one vkCmdTraceRaysKHR per TLAS part, each part looking only nearer than the hits of
// the parts before it.
#include "host/vulkan/vk_clock.h"
#include "host/device_fill.h"
#include "host/scene_variant.h"
#include "host/vulkan/driver_scene.h"
#include "host/vulkan/rt_pipeline.h"
#include "host/vulkan/trace_dispatch.h"
#include "host/vulkan/vk_barriers.h"
#include "host/vulkan/vk_lanes.h"
#include "host/vulkan/vulkan_backends.h"
#include "kernels/kernel_data.h"
#include <algorithm>
#include <chrono>
#include <map>
#include <memory>

namespace masq {
namespace {

using vk::Clock;
using vk::seconds_since;

const char* const kRtPipelineName = "rtpipeline";

// The push constants of kernels/rt_shared.h (RtParams).
struct RtParams {
  std::int32_t ray_count, first, ray_offset, part;
};
static_assert(sizeof(RtParams) == sizeof(kernel::TraceParams));

class RtPipelineBackend final : public Backend {
 public:
  RtPipelineBackend()
      : ctx_(vk::Context::get(kRtPipelineName, DeviceNeed::RayPipeline)),
        layout_(*ctx_, vk::kernel_descriptor_types(), sizeof(RtParams), vk::kRtShaderStages), batch_(*ctx_) {}

  std::string name() const override { return kRtPipelineName; }
  std::string device_name() const override { return ctx_->device_name(); }

  void set_scene(const PackedScene& scene) override {
    auto t0 = Clock::now();
    have_scene_ = false;
    tables_.clear(); // their hit records follow the plan
    features_ = driver_.set(scene);
    have_scene_ = true;
    timing_.scene_seconds = seconds_since(t0);
  }

  void trace(std::span<const kernel::Ray> rays, std::span<kernel::Hit> hits, std::span<kernel::RayStats> stats,
             Query query) override {
    if (!have_scene_) throw Error("rtpipeline: trace called before set_scene");
    driver_.widen_for(rays); // rebuilds keep the plan, so the binding tables stay valid
    const Prepared p = prepare(!stats.empty(), query == Query::Any);
    const bool counters = !stats.empty();
    batch_.run_chunks(kRtPipelineName, layout_, max_launch(), rays, hits, stats,
                      [&](std::uint32_t n) { return launch(p, n, counters); })
        .into(timing_);
  }

  TraceTiming timing() const override { return timing_; }
  std::size_t fill_rays() const override { return fill_rays_for(vk::resident_threads(*ctx_)); }

  // The driver's structures (BLAS compacted) and the binding tables held.
  std::size_t device_bytes() const override {
    std::size_t b = driver_.device_bytes();
    for (const auto& [pipeline, table] : tables_) b += table->bytes();
    return b;
  }

 private:
  struct Prepared {
    const vk::RtPipeline* pipeline;
    const vk::BindingTable* table;
  };

  // Rays in one vkCmdTraceRaysKHR: maxRayDispatchInvocationCount, and a width within
  // maxComputeWorkGroupCount[0] x maxComputeWorkGroupSize[0].
  std::uint64_t max_launch() const {
    const VkPhysicalDeviceLimits& l = ctx_->props().limits;
    return std::min<std::uint64_t>(ctx_->rt_props().maxRayDispatchInvocationCount,
                                   std::uint64_t(l.maxComputeWorkGroupCount[0]) * l.maxComputeWorkGroupSize[0]);
  }

  // One launch of n rays: every TLAS part in turn (part -1 when there is none: misses).
  double launch(const Prepared& p, std::uint32_t n, bool counters) {
    const vk::BindingTable& t = *p.table;
    return layout_.run_timed([&](VkCommandBuffer cmd) {
      vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_RAY_TRACING_KHR, p.pipeline->handle());
      VkDescriptorSet set = layout_.set();
      vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_RAY_TRACING_KHR, layout_.pipeline_layout(), 0, 1, &set, 0,
                              nullptr);
      if (counters && n > 0) {
        vkCmdFillBuffer(cmd, batch_.stats_buffer().handle(), 0, VkDeviceSize{n} * sizeof(kernel::RayStats), 0);
        vk::barrier_after_fill(cmd);
      }
      const std::size_t parts = driver_.part_count();
      for (std::size_t part = 0; part < std::max<std::size_t>(parts, 1); ++part) {
        RtParams pc{static_cast<std::int32_t>(n), parts ? static_cast<std::int32_t>(driver_.part_first(part)) : 0, 0,
                    parts ? static_cast<std::int32_t>(part) : -1};
        vkCmdPushConstants(cmd, layout_.pipeline_layout(), vk::kRtShaderStages, 0, sizeof(pc), &pc);
        ctx_->rt().cmd_trace(cmd, &t.raygen, &t.miss, &t.hit, &t.callable, std::max<std::uint32_t>(n, 1), 1, 1);
        vk::barrier_after_trace_rays(cmd);
      }
    });
  }

  // The pipeline of this variant (created on first use, then kept: compile_seconds
  // covers creation and a warm-up launch, since a driver may compile at first use) and
  // its binding table for the current scene.
  Prepared prepare(bool stats, bool any_hit) {
    const bool addressed = driver_.addressed();
    const KernelVariant v = kernel_variant(features_, {stats, any_hit});
    std::vector<std::uint32_t> key = vk::spec_constants(v, 1);
    key.push_back(addressed ? 1 : 0);
    auto it = pipelines_.find(key);
    if (it == pipelines_.end()) {
      // Made once per context, for every rtpipeline backend object on it (SharedObjects).
      std::shared_ptr<const Compiled> c =
          ctx_->shared().get<Compiled>(layout_.pipeline_key(&kCompiledMaker, key), [&] {
            auto t0 = Clock::now();
            auto made = std::make_shared<Compiled>();
            made->pipeline = std::make_unique<vk::RtPipeline>(*ctx_, layout_, v, addressed, kRtPipelineName);
            batch_.bind_minimal(layout_);
            Prepared warm{made->pipeline.get(), &table(*made->pipeline)};
            launch(warm, 0, false); // ray_count 0: every invocation returns at once
            made->compile_seconds = seconds_since(t0);
            return made;
          });
      it = pipelines_.emplace(std::move(key), std::move(c)).first;
    }
    timing_.compile_seconds = it->second->compile_seconds;
    return {it->second->pipeline.get(), &table(*it->second->pipeline)};
  }

  const vk::BindingTable& table(const vk::RtPipeline& p) {
    auto it = tables_.find(&p);
    if (it == tables_.end())
      it = tables_.emplace(&p, std::make_unique<vk::BindingTable>(*ctx_, p, driver_.plan(), kRtPipelineName)).first;
    return *it->second;
  }

  struct Compiled {
    std::unique_ptr<vk::RtPipeline> pipeline;
    double compile_seconds = 0; // creation and the warm-up launch of the backend that made it
  };
  static constexpr char kCompiledMaker = 0; // SharedObjects key of the pipelines

  std::shared_ptr<vk::Context> ctx_;
  vk::KernelLayout layout_;
  vk::RayBatch batch_;
  vk::DriverScene driver_{*ctx_, layout_, kRtPipelineName};
  std::map<std::vector<std::uint32_t>, std::shared_ptr<const Compiled>> pipelines_;  // by variant
  std::map<const vk::RtPipeline*, std::unique_ptr<vk::BindingTable>> tables_;          // for the current scene
  KernelFeatures features_;
  bool have_scene_ = false;
  TraceTiming timing_;
};

} // namespace

std::unique_ptr<Backend> make_rtpipeline_backend() { return std::make_unique<RtPipelineBackend>(); }

} // namespace masq
