#include "host/vulkan/vk_pipeline.h"
#include "host/vulkan/vk_shader_limits.h"
#include "host/vulkan/vk_barriers.h"
#include <fmt/format.h>
#include <chrono>
#include <cstdio>
#include <map>
#include <string>

namespace masq::vk {

KernelLayout::KernelLayout(Context& ctx, std::vector<VkDescriptorType> types, std::uint32_t push_constant_bytes,
                           VkShaderStageFlags stages)
    : ctx_(ctx), types_(std::move(types)), push_bytes_(push_constant_bytes), stages_(stages) {
  std::vector<VkDescriptorSetLayoutBinding> bindings;
  std::map<VkDescriptorType, std::uint32_t> counts;
  for (std::uint32_t i = 0; i < types_.size(); ++i) {
    VkDescriptorSetLayoutBinding b{};
    b.binding = i;
    b.descriptorType = types_[i];
    b.descriptorCount = 1;
    b.stageFlags = stages_;
    bindings.push_back(b);
    ++counts[types_[i]];
  }
  try {
    VkDescriptorSetLayoutCreateInfo dl{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
    dl.bindingCount = static_cast<std::uint32_t>(bindings.size());
    dl.pBindings = bindings.data();
    MASQ_VK_CHECK(vkCreateDescriptorSetLayout(ctx_.device(), &dl, nullptr, &set_layout_));
    VkPushConstantRange pcr{stages_, 0, push_bytes_};
    VkPipelineLayoutCreateInfo pl{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
    pl.setLayoutCount = 1;
    pl.pSetLayouts = &set_layout_;
    pl.pushConstantRangeCount = push_bytes_ ? 1 : 0;
    pl.pPushConstantRanges = &pcr;
    MASQ_VK_CHECK(vkCreatePipelineLayout(ctx_.device(), &pl, nullptr, &pipeline_layout_));
    std::vector<VkDescriptorPoolSize> sizes;
    for (auto [type, n] : counts) sizes.push_back({type, n});
    VkDescriptorPoolCreateInfo dp{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
    dp.maxSets = 1;
    dp.poolSizeCount = static_cast<std::uint32_t>(sizes.size());
    dp.pPoolSizes = sizes.data();
    MASQ_VK_CHECK(vkCreateDescriptorPool(ctx_.device(), &dp, nullptr, &pool_));
    VkDescriptorSetAllocateInfo ai{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
    ai.descriptorPool = pool_;
    ai.descriptorSetCount = 1;
    ai.pSetLayouts = &set_layout_;
    MASQ_VK_CHECK(vkAllocateDescriptorSets(ctx_.device(), &ai, &set_));
    if (ctx_.timestamp_valid_bits() > 0) {
      VkQueryPoolCreateInfo qp{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
      qp.queryType = VK_QUERY_TYPE_TIMESTAMP;
      qp.queryCount = 2;
      MASQ_VK_CHECK(vkCreateQueryPool(ctx_.device(), &qp, nullptr, &queries_));
    }
  } catch (...) {
    release();
    throw;
  }
}

KernelLayout::~KernelLayout() { release(); }

void KernelLayout::release() noexcept {
  if (queries_) vkDestroyQueryPool(ctx_.device(), queries_, nullptr);
  if (pool_) vkDestroyDescriptorPool(ctx_.device(), pool_, nullptr);
  if (pipeline_layout_) vkDestroyPipelineLayout(ctx_.device(), pipeline_layout_, nullptr);
  if (set_layout_) vkDestroyDescriptorSetLayout(ctx_.device(), set_layout_, nullptr);
  queries_ = VK_NULL_HANDLE;
  pool_ = VK_NULL_HANDLE;
  pipeline_layout_ = VK_NULL_HANDLE;
  set_layout_ = VK_NULL_HANDLE;
}

VkShaderModule create_shader_module(Context& ctx, std::span<const std::uint32_t> spirv) {
  const std::vector<std::uint32_t> code = device_spirv(ctx, spirv); // float controls (vk_shader_limits.h)
  VkShaderModuleCreateInfo smi{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
  smi.codeSize = code.size() * sizeof(std::uint32_t);
  smi.pCode = code.data();
  VkShaderModule module = VK_NULL_HANDLE;
  MASQ_VK_CHECK(vkCreateShaderModule(ctx.device(), &smi, nullptr, &module));
  return module;
}

VkPipeline KernelLayout::create_pipeline(std::span<const std::uint32_t> spirv,
                                         std::span<const std::uint32_t> values) {
  VkShaderModule module = create_shader_module(ctx_, spirv);
  std::vector<VkSpecializationMapEntry> entries;
  for (std::uint32_t i = 0; i < values.size(); ++i)
    entries.push_back({i, static_cast<std::uint32_t>(i * sizeof(std::uint32_t)), sizeof(std::uint32_t)});
  VkSpecializationInfo spec{};
  spec.mapEntryCount = static_cast<std::uint32_t>(entries.size());
  spec.pMapEntries = entries.data();
  spec.dataSize = values.size_bytes();
  spec.pData = values.data();
  VkComputePipelineCreateInfo cpi{VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO};
  cpi.stage.sType = VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO;
  cpi.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
  cpi.stage.module = module;
  cpi.stage.pName = "main";
  cpi.stage.pSpecializationInfo = values.empty() ? nullptr : &spec;
  cpi.layout = pipeline_layout_;
  if (ctx_.pipeline_statistics()) cpi.flags |= VK_PIPELINE_CREATE_CAPTURE_STATISTICS_BIT_KHR;
  VkPipeline pipeline = VK_NULL_HANDLE;
  VkResult r = vkCreateComputePipelines(ctx_.device(), ctx_.pipeline_cache(), 1, &cpi, nullptr, &pipeline);
  vkDestroyShaderModule(ctx_.device(), module, nullptr);
  if (r != VK_SUCCESS) throw_vk_error("vkCreateComputePipelines", r, __FILE__, __LINE__);
  if (ctx_.pipeline_statistics()) print_pipeline_statistics(pipeline, spirv.size(), values);
  return pipeline;
}

// One line per executable of the pipeline: its name and every statistic the driver
// reports (NVIDIA: registers, shared and local memory...), with the module's size and
// the specialization constants that tell the variant apart.
void KernelLayout::print_pipeline_statistics(VkPipeline pipeline, std::size_t module_words,
                                             std::span<const std::uint32_t> values) const {
  VkPipelineInfoKHR info{VK_STRUCTURE_TYPE_PIPELINE_INFO_KHR};
  info.pipeline = pipeline;
  std::uint32_t n = 0;
  if (ctx_.executable_properties()(ctx_.device(), &info, &n, nullptr) != VK_SUCCESS) return;
  std::vector<VkPipelineExecutablePropertiesKHR> exes(n, {VK_STRUCTURE_TYPE_PIPELINE_EXECUTABLE_PROPERTIES_KHR});
  if (ctx_.executable_properties()(ctx_.device(), &info, &n, exes.data()) != VK_SUCCESS) return;
  std::string spec;
  for (std::uint32_t v : values) {
    if (!spec.empty()) spec += ',';
    spec += std::to_string(v);
  }
  for (std::uint32_t e = 0; e < n; ++e) {
    VkPipelineExecutableInfoKHR ei{VK_STRUCTURE_TYPE_PIPELINE_EXECUTABLE_INFO_KHR};
    ei.pipeline = pipeline;
    ei.executableIndex = e;
    std::uint32_t ns = 0;
    if (ctx_.executable_statistics()(ctx_.device(), &ei, &ns, nullptr) != VK_SUCCESS) continue;
    std::vector<VkPipelineExecutableStatisticKHR> stats(ns, {VK_STRUCTURE_TYPE_PIPELINE_EXECUTABLE_STATISTIC_KHR});
    if (ctx_.executable_statistics()(ctx_.device(), &ei, &ns, stats.data()) != VK_SUCCESS) continue;
    std::string line;
    for (const VkPipelineExecutableStatisticKHR& s : stats) {
      line += fmt::format("; {} ", s.name);
      switch (s.format) {
        case VK_PIPELINE_EXECUTABLE_STATISTIC_FORMAT_BOOL32_KHR: line += s.value.b32 ? "yes" : "no"; break;
        case VK_PIPELINE_EXECUTABLE_STATISTIC_FORMAT_INT64_KHR: line += std::to_string(s.value.i64); break;
        case VK_PIPELINE_EXECUTABLE_STATISTIC_FORMAT_UINT64_KHR: line += std::to_string(s.value.u64); break;
        case VK_PIPELINE_EXECUTABLE_STATISTIC_FORMAT_FLOAT64_KHR: line += fmt::format("{:g}", s.value.f64); break;
        default: line += "?";
      }
    }
    std::fprintf(stderr, "masq: vulkan pipeline statistics: module %zu words, spec [%s], executable '%s'%s\n",
                 module_words, spec.c_str(), exes[e].name, line.c_str());
  }
}

void KernelLayout::destroy_pipeline(VkPipeline p) {
  if (p) vkDestroyPipeline(ctx_.device(), p, nullptr);
}

void KernelLayout::bind_buffer(std::uint32_t binding, const Buffer& buffer) {
  VkDescriptorBufferInfo info{buffer.handle(), 0, VK_WHOLE_SIZE};
  VkWriteDescriptorSet w{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
  w.dstSet = set_;
  w.dstBinding = binding;
  w.descriptorCount = 1;
  w.descriptorType = types_.at(binding);
  w.pBufferInfo = &info;
  vkUpdateDescriptorSets(ctx_.device(), 1, &w, 0, nullptr);
}

void KernelLayout::bind_acceleration_structure(std::uint32_t binding, VkAccelerationStructureKHR as) {
  VkWriteDescriptorSetAccelerationStructureKHR asw{
      VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET_ACCELERATION_STRUCTURE_KHR};
  asw.accelerationStructureCount = 1;
  asw.pAccelerationStructures = &as;
  VkWriteDescriptorSet w{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET, &asw};
  w.dstSet = set_;
  w.dstBinding = binding;
  w.descriptorCount = 1;
  w.descriptorType = VK_DESCRIPTOR_TYPE_ACCELERATION_STRUCTURE_KHR;
  vkUpdateDescriptorSets(ctx_.device(), 1, &w, 0, nullptr);
}

double KernelLayout::dispatch(VkPipeline pipeline, const void* push_constants, std::uint32_t groups) {
  return run_timed([&](VkCommandBuffer cmd) {
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline);
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline_layout_, 0, 1, &set_, 0, nullptr);
    if (push_bytes_) vkCmdPushConstants(cmd, pipeline_layout_, stages_, 0, push_bytes_, push_constants);
    if (groups > 0) vkCmdDispatch(cmd, groups, 1, 1);
    barrier_after_dispatch(cmd); // host/vulkan/vk_barriers.h
  });
}

double KernelLayout::run_timed(const std::function<void(VkCommandBuffer)>& record) {
  VkCommandBuffer cmd = ctx_.begin_commands();
  if (queries_) {
    vkCmdResetQueryPool(cmd, queries_, 0, 2);
    vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, queries_, 0);
  }
  record(cmd);
  if (queries_) vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, queries_, 1);
  ctx_.submit_and_wait(cmd);
  if (!queries_) return 0.0;
  std::uint64_t ts[2] = {0, 0};
  MASQ_VK_CHECK(vkGetQueryPoolResults(ctx_.device(), queries_, 0, 2, sizeof(ts), ts, sizeof(std::uint64_t),
                                      VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT));
  std::uint64_t mask = ctx_.timestamp_valid_bits() >= 64 ? ~0ull : ((1ull << ctx_.timestamp_valid_bits()) - 1);
  std::uint64_t ticks = ((ts[1] & mask) - (ts[0] & mask)) & mask;
  return static_cast<double>(ticks) * static_cast<double>(ctx_.props().limits.timestampPeriod) * 1e-9;
}

PipelineVariants::~PipelineVariants() {
  for (auto& [spec, v] : cache_) layout_.destroy_pipeline(v.pipeline);
}

const PipelineVariants::Variant& PipelineVariants::get(const std::vector<std::uint32_t>& spec,
                                                       const std::function<void(VkPipeline)>& warm_up) {
  auto it = cache_.find(spec);
  if (it != cache_.end()) return it->second;
  auto t0 = std::chrono::steady_clock::now();
  Variant v;
  v.pipeline = layout_.create_pipeline(spirv_, spec);
  try {
    warm_up(v.pipeline);
  } catch (...) {
    layout_.destroy_pipeline(v.pipeline);
    throw;
  }
  v.compile_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return cache_.emplace(spec, v).first->second;
}

} // namespace masq::vk
