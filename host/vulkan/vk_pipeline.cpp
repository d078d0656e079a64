#include "host/vulkan/vk_pipeline.h"
#include "host/vulkan/vk_shader_limits.h"
#include "host/vulkan/spirv_specialize.h"
#include "host/vulkan/vk_barriers.h"
#include <fmt/format.h>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <map>
#include <string>
#include <utility>

namespace masq::vk {

namespace {
const char kLayoutsMaker = 0; // SharedObjects key of KernelLayout's layouts
} // namespace

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
  const VkDevice device = ctx_.device();
  SharedObjects::Key key{&kLayoutsMaker, {push_bytes_, stages_}};
  key.values.insert(key.values.end(), types_.begin(), types_.end());
  layouts_ = ctx_.shared().get<Layouts>(key, [&] {
    auto made = std::make_shared<Layouts>();
    VkDescriptorSetLayoutCreateInfo dl{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
    dl.bindingCount = static_cast<std::uint32_t>(bindings.size());
    dl.pBindings = bindings.data();
    made->set_layout = {device, vkDestroyDescriptorSetLayout};
    MASQ_VK_CHECK(vkCreateDescriptorSetLayout(device, &dl, nullptr, made->set_layout.put()));
    const VkDescriptorSetLayout set_layout = made->set_layout.get();
    VkPushConstantRange pcr{stages_, 0, push_bytes_};
    VkPipelineLayoutCreateInfo pl{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
    pl.setLayoutCount = 1;
    pl.pSetLayouts = &set_layout;
    pl.pushConstantRangeCount = push_bytes_ ? 1 : 0;
    pl.pPushConstantRanges = &pcr;
    made->pipeline_layout = {device, vkDestroyPipelineLayout};
    MASQ_VK_CHECK(vkCreatePipelineLayout(device, &pl, nullptr, made->pipeline_layout.put()));
    return made;
  });
  const VkDescriptorSetLayout set_layout = layouts_->set_layout.get();
  std::vector<VkDescriptorPoolSize> sizes;
  for (auto [type, n] : counts) sizes.push_back({type, n});
  VkDescriptorPoolCreateInfo dp{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
  dp.maxSets = 1;
  dp.poolSizeCount = static_cast<std::uint32_t>(sizes.size());
  dp.pPoolSizes = sizes.data();
  pool_ = {device, vkDestroyDescriptorPool};
  MASQ_VK_CHECK(vkCreateDescriptorPool(device, &dp, nullptr, pool_.put()));
  VkDescriptorSetAllocateInfo ai{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
  ai.descriptorPool = pool_.get();
  ai.descriptorSetCount = 1;
  ai.pSetLayouts = &set_layout;
  MASQ_VK_CHECK(vkAllocateDescriptorSets(device, &ai, &set_));
  if (ctx_.timestamp_valid_bits() > 0) {
    VkQueryPoolCreateInfo qp{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
    qp.queryType = VK_QUERY_TYPE_TIMESTAMP;
    qp.queryCount = 2;
    queries_ = {device, vkDestroyQueryPool};
    MASQ_VK_CHECK(vkCreateQueryPool(device, &qp, nullptr, queries_.put()));
  }
}

SharedObjects::Key KernelLayout::pipeline_key(const void* maker, std::vector<std::uint32_t> values) const {
  const VkPipelineLayout layout = pipeline_layout();
  std::uint64_t handle = 0; // a pointer or a 64-bit integer, as the platform defines it
  std::memcpy(&handle, &layout, sizeof layout);
  values.push_back(static_cast<std::uint32_t>(handle));
  values.push_back(static_cast<std::uint32_t>(handle >> 32));
  values.push_back(specialize_on_host() ? 1u : 0u);
  return {maker, std::move(values)};
}

DeviceOwned<VkShaderModule> create_shader_module(Context& ctx, std::span<const std::uint32_t> spirv,
                                                 std::span<const std::uint32_t> values) {
  const std::vector<std::uint32_t> code = specialize_on_host() && !values.empty()
                                              ? device_spirv(ctx, with_constants_frozen(spirv, values))
                                              : device_spirv(ctx, spirv); // float controls (vk_shader_limits.h)
  VkShaderModuleCreateInfo smi{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
  smi.codeSize = code.size() * sizeof(std::uint32_t);
  smi.pCode = code.data();
  DeviceOwned<VkShaderModule> module(ctx.device(), vkDestroyShaderModule);
  MASQ_VK_CHECK(vkCreateShaderModule(ctx.device(), &smi, nullptr, module.put()));
  return module;
}

DeviceOwned<VkPipeline> KernelLayout::create_pipeline(std::span<const std::uint32_t> spirv,
                                                      std::span<const std::uint32_t> values) {
  DeviceOwned<VkShaderModule> module = create_shader_module(ctx_, spirv, values);
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
  cpi.stage.module = module.get();
  cpi.stage.pName = "main";
  cpi.stage.pSpecializationInfo = values.empty() ? nullptr : &spec;
  cpi.layout = pipeline_layout();
  if (ctx_.pipeline_statistics()) cpi.flags |= VK_PIPELINE_CREATE_CAPTURE_STATISTICS_BIT_KHR;
  DeviceOwned<VkPipeline> pipeline(ctx_.device(), vkDestroyPipeline);
  VkResult r = vkCreateComputePipelines(ctx_.device(), ctx_.pipeline_cache(), 1, &cpi, nullptr, pipeline.put());
  module.reset(); // the pipeline keeps what it needs
  if (r != VK_SUCCESS) {
    pipeline.release();
    throw_vk_error("vkCreateComputePipelines", r, __FILE__, __LINE__);
  }
  if (ctx_.pipeline_statistics()) print_pipeline_statistics(pipeline.get(), spirv.size(), values);
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
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline_layout(), 0, 1, &set_, 0, nullptr);
    if (push_bytes_) vkCmdPushConstants(cmd, pipeline_layout(), stages_, 0, push_bytes_, push_constants);
    if (groups > 0) vkCmdDispatch(cmd, groups, 1, 1);
    barrier_after_dispatch(cmd); // host/vulkan/vk_barriers.h
  });
}

double KernelLayout::run_timed(const std::function<void(VkCommandBuffer)>& record) {
  VkCommandBuffer cmd = ctx_.begin_commands();
  if (queries_) {
    vkCmdResetQueryPool(cmd, queries_.get(), 0, 2);
    vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, queries_.get(), 0);
  }
  record(cmd);
  if (queries_) vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, queries_.get(), 1);
  ctx_.submit_and_wait(cmd);
  if (!queries_) return 0.0;
  std::uint64_t ts[2] = {0, 0};
  MASQ_VK_CHECK(vkGetQueryPoolResults(ctx_.device(), queries_.get(), 0, 2, sizeof(ts), ts, sizeof(std::uint64_t),
                                      VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT));
  std::uint64_t mask = ctx_.timestamp_valid_bits() >= 64 ? ~0ull : ((1ull << ctx_.timestamp_valid_bits()) - 1);
  std::uint64_t ticks = ((ts[1] & mask) - (ts[0] & mask)) & mask;
  return static_cast<double>(ticks) * static_cast<double>(ctx_.props().limits.timestampPeriod) * 1e-9;
}

const PipelineVariants::Variant& PipelineVariants::get(const std::vector<std::uint32_t>& spec,
                                                       const std::function<void(VkPipeline)>& warm_up) {
  auto it = cache_.find(spec);
  if (it != cache_.end()) return *it->second;
  const SharedObjects::Key key = layout_.pipeline_key(spirv_.data(), spec);
  std::shared_ptr<const Variant> v = layout_.context().shared().get<Variant>(key, [&] {
    auto t0 = std::chrono::steady_clock::now();
    auto made = std::make_shared<Variant>();
    made->pipeline = layout_.create_pipeline(spirv_, spec);
    warm_up(made->pipeline.get());
    made->compile_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return made;
  });
  return *cache_.emplace(spec, std::move(v)).first->second;
}

} // namespace masq::vk
