// Compute-kernel plumbing shared by the Vulkan backends and the layout test: one
// descriptor set (bindings 0..n-1, storage buffers unless told otherwise), a push
// constant block, pipelines specialised by constant id, and a timed dispatch.
#pragma once
#include "host/vulkan/vk_buffer.h"
#include <array>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <span>
#include <vector>

namespace masq::vk {

// A shader module of `spirv` as the device gets it: its specialization constants frozen
// at `values` (values[i] to constant_id i; host/vulkan/spirv_specialize.h) unless
// MASQ_VK_SPECIALIZE=driver, then float controls (device_spirv,
// host/vulkan/vk_shader_limits.h). The pipeline still passes `values` as its
// VkSpecializationInfo: an id the frozen module no longer has is ignored.
DeviceOwned<VkShaderModule> create_shader_module(Context& ctx, std::span<const std::uint32_t> spirv,
                                                 std::span<const std::uint32_t> values);

class KernelLayout {
 public:
  // types[i]: descriptor type of binding i; `stages`: the shader stages that see the
  // bindings and the push constants (the ray-tracing pipeline's, for rtpipeline).
  KernelLayout(Context& ctx, std::vector<VkDescriptorType> types, std::uint32_t push_constant_bytes,
               VkShaderStageFlags stages = VK_SHADER_STAGE_COMPUTE_BIT);
  KernelLayout(const KernelLayout&) = delete;
  KernelLayout& operator=(const KernelLayout&) = delete;

  // Specialisation constants: values[i] goes to constant_id i (4 bytes each; bools as
  // VkBool32).
  DeviceOwned<VkPipeline> create_pipeline(std::span<const std::uint32_t> spirv, std::span<const std::uint32_t> values);

  void bind_buffer(std::uint32_t binding, const Buffer& buffer);
  void bind_acceleration_structure(std::uint32_t binding, VkAccelerationStructureKHR as);

  // Records and runs one dispatch of `groups` work groups; waits for it. Returns the
  // device time in seconds from timestamp queries (0 when the queue has none).
  double dispatch(VkPipeline pipeline, const void* push_constants, std::uint32_t groups);
  // Records `record` into one command buffer between two timestamps, runs it and waits;
  // returns the device time in seconds as dispatch() does. `record` must not throw.
  double run_timed(const std::function<void(VkCommandBuffer)>& record);

  VkDescriptorSet set() const { return set_; }
  Context& context() const { return ctx_; }
  // The key of a pipeline made with this layout in the context's SharedObjects: `maker`
  // and `values` (the module and its constants), the pipeline layout's handle, so
  // that layouts of other bindings never share a pipeline, and who applies the constants
  // (MASQ_VK_SPECIALIZE: backend objects made after the knob changes get their own pipelines).
  SharedObjects::Key pipeline_key(const void* maker, std::vector<std::uint32_t> values) const;
  VkPipelineLayout pipeline_layout() const { return layouts_->pipeline_layout.get(); }
  VkShaderStageFlags stages() const { return stages_; }
  std::uint32_t push_constant_bytes() const { return push_bytes_; }

 private:
  // MASQ_VK_PIPELINE_STATS=1 (Context::pipeline_statistics): the driver's statistics of
  // each executable of `pipeline`, one line each on stderr.
  void print_pipeline_statistics(VkPipeline pipeline, std::size_t module_words,
                                 std::span<const std::uint32_t> values) const;
  Context& ctx_;
  std::vector<VkDescriptorType> types_;
  std::uint32_t push_bytes_ = 0;
  VkShaderStageFlags stages_ = VK_SHADER_STAGE_COMPUTE_BIT;
  // The set layout and pipeline layout of these bindings, one pair per context (its
  // SharedObjects) for every KernelLayout of the same bindings, push constants and
  // stages: a pipeline made with one can then run with every other's descriptor set.
  struct Layouts {
    DeviceOwned<VkDescriptorSetLayout> set_layout;
    DeviceOwned<VkPipelineLayout> pipeline_layout;
  };
  std::shared_ptr<const Layouts> layouts_;
  // In the order they are made: each goes before the one it was made with.
  DeviceOwned<VkDescriptorPool> pool_;
  VkDescriptorSet set_ = VK_NULL_HANDLE; // freed with pool_
  DeviceOwned<VkQueryPool> queries_;
};

// The pipelines of one shader, one per specialisation (value i -> constant id i), created on
// first use and kept by the context (its SharedObjects), so that every backend object on
// one device runs the same pipeline for the same variant. compile_seconds covers
// creation plus the warm-up dispatch of the caller that made it, because lavapipe
// compiles at the first dispatch; it is the variant's compile time, paid once per device.
class PipelineVariants {
 public:
  struct Variant {
    DeviceOwned<VkPipeline> pipeline;
    double compile_seconds = 0;
  };
  PipelineVariants(KernelLayout& layout, std::span<const std::uint32_t> spirv) : layout_(layout), spirv_(spirv) {}
  PipelineVariants(const PipelineVariants&) = delete;
  PipelineVariants& operator=(const PipelineVariants&) = delete;
  const Variant& get(const std::vector<std::uint32_t>& spec, const std::function<void(VkPipeline)>& warm_up);

 private:
  KernelLayout& layout_;
  std::span<const std::uint32_t> spirv_;
  std::map<std::vector<std::uint32_t>, std::shared_ptr<const Variant>> cache_; // this object's look-ups
};

} // namespace masq::vk
