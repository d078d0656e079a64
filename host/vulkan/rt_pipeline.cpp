#include "host/vulkan/vk_buffer.h"
#include "host/vulkan/rt_pipeline.h"
#include "scenes/prim_table.h"
#include "host/limit_knob.h"
#include "host/vulkan/trace_dispatch.h"
#include "host/vulkan/vk_devices.h"
#include "host/vulkan/vulkan_backends.h"
#include "spirv/rtpipeline_rchit_addr_spv.h"
#include "spirv/rtpipeline_rchit_spv.h"
#include "spirv/rtpipeline_rgen_addr_spv.h"
#include "spirv/rtpipeline_rgen_spv.h"
#include "spirv/rtpipeline_rint_addr_spv.h"
#include "spirv/rtpipeline_rint_spv.h"
#include "spirv/rtpipeline_rmiss_addr_spv.h"
#include "spirv/rtpipeline_rmiss_spv.h"
#include "spirv/rtpipeline_triangle_rahit_addr_spv.h"
#include "spirv/rtpipeline_triangle_rahit_spv.h"
#include "spirv/rtpipeline_triangle_rchit_addr_spv.h"
#include "spirv/rtpipeline_triangle_rchit_spv.h"
#include <fmt/format.h>
#include <cstring>
#include <memory>

namespace masq::vk {
namespace {

// The pipeline's modules, scene arrays bound or read by address (kernels/kernel_data.h).
struct RtModules {
  std::span<const std::uint32_t> raygen, miss, closest, intersection, triangle_any, triangle_closest;
};
RtModules rt_modules(bool addressed) {
  if (addressed)
    return {rtpipeline_rgen_addr_spv, rtpipeline_rmiss_addr_spv,           rtpipeline_rchit_addr_spv,
            rtpipeline_rint_addr_spv, rtpipeline_triangle_rahit_addr_spv, rtpipeline_triangle_rchit_addr_spv};
  return {rtpipeline_rgen_spv, rtpipeline_rmiss_spv,           rtpipeline_rchit_spv,
          rtpipeline_rint_spv, rtpipeline_triangle_rahit_spv, rtpipeline_triangle_rchit_spv};
}


// Specialisation constants as VkSpecializationInfo points at them (value i -> id i).
struct Specialization {
  std::vector<std::uint32_t> values;
  std::vector<VkSpecializationMapEntry> entries;
  VkSpecializationInfo info{};
  explicit Specialization(std::vector<std::uint32_t> v) : values(std::move(v)) {
    for (std::uint32_t i = 0; i < values.size(); ++i)
      entries.push_back({i, static_cast<std::uint32_t>(i * sizeof(std::uint32_t)), sizeof(std::uint32_t)});
    info.mapEntryCount = static_cast<std::uint32_t>(entries.size());
    info.pMapEntries = entries.data();
    info.dataSize = values.size() * sizeof(std::uint32_t);
    info.pData = values.data();
  }
  Specialization(const Specialization&) = delete;
};

} // namespace

RtPipeline::RtPipeline(Context& ctx, KernelLayout& layout, const KernelVariant& v, bool addressed,
                       const char* backend)
    : ctx_(ctx), pipeline_(ctx.device(), vkDestroyPipeline) {
  const RtModules m = rt_modules(addressed);
  std::vector<DeviceOwned<VkShaderModule>> modules; // destroyed once the pipeline is made
  // A module per stage and specialization: frozen on the host, each intersection
  // stage's module holds its own type's code only.
  auto module = [&](std::span<const std::uint32_t> spirv, const Specialization& spec) {
    modules.push_back(create_shader_module(ctx_, spirv, spec.values));
    return modules.back().get();
  };
  // The variant's constants for every stage; each intersection stage its own copy with
  // only its type's switch left on (kHitGroups).
  const Specialization common(spec_constants(v, 1));
  std::vector<std::unique_ptr<Specialization>> per_type;
  std::vector<VkPipelineShaderStageCreateInfo> stages;
  auto stage = [&](VkShaderStageFlagBits bit, VkShaderModule mod, const VkSpecializationInfo* spec) {
    VkPipelineShaderStageCreateInfo s{VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO};
    s.stage = bit;
    s.module = mod;
    s.pName = "main";
    s.pSpecializationInfo = spec;
    stages.push_back(s);
    return static_cast<std::uint32_t>(stages.size() - 1);
  };
  std::vector<VkRayTracingShaderGroupCreateInfoKHR> groups;
  auto group = [&](VkRayTracingShaderGroupTypeKHR type) {
    VkRayTracingShaderGroupCreateInfoKHR g{VK_STRUCTURE_TYPE_RAY_TRACING_SHADER_GROUP_CREATE_INFO_KHR};
    g.type = type;
    g.generalShader = g.closestHitShader = g.anyHitShader = g.intersectionShader = VK_SHADER_UNUSED_KHR;
    groups.push_back(g);
    return &groups.back();
  };
  groups.reserve(kFirstHitGroup + std::size(kHitGroups));
  group(VK_RAY_TRACING_SHADER_GROUP_TYPE_GENERAL_KHR)->generalShader =
      stage(VK_SHADER_STAGE_RAYGEN_BIT_KHR, module(m.raygen, common), &common.info);
  group(VK_RAY_TRACING_SHADER_GROUP_TYPE_GENERAL_KHR)->generalShader =
      stage(VK_SHADER_STAGE_MISS_BIT_KHR, module(m.miss, common), &common.info);
  const std::uint32_t closest_stage =
      stage(VK_SHADER_STAGE_CLOSEST_HIT_BIT_KHR, module(m.closest, common), &common.info);
  for (const HitGroupRow& row : kHitGroups) {
    if (scene_prim_row_of_kernel_type(row.prim_type).mesh) { // the driver intersects triangles itself
      VkRayTracingShaderGroupCreateInfoKHR* g = group(VK_RAY_TRACING_SHADER_GROUP_TYPE_TRIANGLES_HIT_GROUP_KHR);
      g->closestHitShader =
          stage(VK_SHADER_STAGE_CLOSEST_HIT_BIT_KHR, module(m.triangle_closest, common), &common.info);
      g->anyHitShader = stage(VK_SHADER_STAGE_ANY_HIT_BIT_KHR, module(m.triangle_any, common), &common.info);
      continue;
    }
    KernelVariant only = v;
    for (const HitGroupRow& other : kHitGroups)
      if (other.prim_type != row.prim_type) only.*other.have = 0;
    per_type.push_back(std::make_unique<Specialization>(spec_constants(only, 1)));
    VkRayTracingShaderGroupCreateInfoKHR* g = group(VK_RAY_TRACING_SHADER_GROUP_TYPE_PROCEDURAL_HIT_GROUP_KHR);
    g->intersectionShader = stage(VK_SHADER_STAGE_INTERSECTION_BIT_KHR, module(m.intersection, *per_type.back()),
                                  &per_type.back()->info);
    g->closestHitShader = closest_stage;
  }
  VkRayTracingPipelineCreateInfoKHR ci{VK_STRUCTURE_TYPE_RAY_TRACING_PIPELINE_CREATE_INFO_KHR};
  ci.stageCount = static_cast<std::uint32_t>(stages.size());
  ci.pStages = stages.data();
  ci.groupCount = static_cast<std::uint32_t>(groups.size());
  ci.pGroups = groups.data();
  ci.maxPipelineRayRecursionDepth = kRtRecursionDepth;
  ci.layout = layout.pipeline_layout();
  VkResult r =
      ctx_.rt().create(ctx_.device(), VK_NULL_HANDLE, ctx_.pipeline_cache(), 1, &ci, nullptr, pipeline_.put());
  if (r != VK_SUCCESS) {
    pipeline_.release();
    throw Error(fmt::format("{}: vkCreateRayTracingPipelinesKHR: {}", backend, result_name(r)));
  }
  const std::size_t size = ctx_.rt_props().shaderGroupHandleSize;
  handles_.resize(size * groups.size());
  MASQ_VK_CHECK(ctx_.rt().group_handles(ctx_.device(), pipeline_.get(), 0,
                                        static_cast<std::uint32_t>(groups.size()), handles_.size(), handles_.data()));
}

std::span<const std::byte> RtPipeline::group_handle(std::uint32_t g) const {
  const std::size_t size = ctx_.rt_props().shaderGroupHandleSize;
  return std::span<const std::byte>(handles_).subspan(g * size, size);
}

BindingTable::BindingTable(Context& ctx, const RtPipeline& pipeline, const RayQueryPlan& plan, const char* backend) {
  const VkPhysicalDeviceRayTracingPipelinePropertiesKHR& p = ctx.rt_props();
  const VkDeviceSize stride =
      align_up(p.shaderGroupHandleSize + kRtRecordDataBytes, std::max<VkDeviceSize>(p.shaderGroupHandleAlignment, 1));
  // No driver reports a stride too small for masq's records: only MASQ_RT_MAX_GROUP_STRIDE lowers it.
  const std::uint64_t max_stride = lowered_limit(backend, p.maxShaderGroupStride, Knob::RtMaxGroupStride);
  if (stride > max_stride)
    throw Error(fmt::format("{}: a hit record takes {} bytes; the device allows {} (maxShaderGroupStride)", backend,
                            stride, max_stride));
  const VkDeviceSize base = std::max<VkDeviceSize>(p.shaderGroupBaseAlignment, 1);
  const std::size_t hit_records = sbt_record_count(plan);
  const VkDeviceSize raygen_at = 0, miss_at = align_up(stride, base), hit_at = miss_at + align_up(stride, base);
  // The buffer's own address is only as aligned as its memory: one base alignment more
  // lets the table start on a multiple of it.
  const VkDeviceSize bytes = hit_at + hit_records * stride + base;
  if (bytes > ctx.max_allocation_bytes())
    throw Error(fmt::format("{}: the shader binding table of {} hit records needs {} bytes in one buffer; the device "
                            "allows {} ({})",
                            backend, hit_records, bytes, ctx.max_allocation_bytes(), ctx.max_allocation_name()));
  std::vector<std::byte> table(bytes - base);
  auto put = [&](VkDeviceSize at, std::uint32_t group, std::int32_t blas) {
    std::span<const std::byte> h = pipeline.group_handle(group);
    std::memcpy(table.data() + at, h.data(), h.size());
    const std::int32_t data[kRtRecordDataBytes / 4] = {blas, 0, 0, 0}; // kernels/rt_shared.h, RtRecord
    std::memcpy(table.data() + at + h.size(), data, sizeof(data));
  };
  put(raygen_at, kRaygenGroup, -1);
  put(miss_at, kMissGroup, -1);
  for (std::size_t b = 0; b < plan.blas.size(); ++b)
    put(hit_at + b * stride, kFirstHitGroup + static_cast<std::uint32_t>(plan.blas[b].type),
        static_cast<std::int32_t>(b));
  for (const HitGroupRow& row : kHitGroups) // masquerade records, by primitive type
    put(hit_at + (plan.blas.size() + std::size_t(row.prim_type)) * stride,
        kFirstHitGroup + static_cast<std::uint32_t>(row.prim_type), -1);
  buffer_ = Buffer(ctx, bytes, VK_BUFFER_USAGE_SHADER_BINDING_TABLE_BIT_KHR | VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT);
  const VkDeviceAddress a = align_up(buffer_.address(), base);
  buffer_.upload(table.data(), table.size(), a - buffer_.address());
  raygen = {a + raygen_at, stride, stride};
  miss = {a + miss_at, stride, stride};
  hit = {a + hit_at, stride, hit_records * stride};
}

} // namespace masq::vk
