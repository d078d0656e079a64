#include "host/vulkan/vk_barriers.h"

namespace masq::vk {
namespace {

// Who may touch a buffer around a copy: shaders, other copies, and the builds of a
// context with driver structures (the build stage needs the accelerationStructure
// feature, the ray-tracing stage the rayTracingPipeline one).
VkPipelineStageFlags device_stages(const Context& ctx) {
  VkPipelineStageFlags s = ctx.shader_stages() | VK_PIPELINE_STAGE_TRANSFER_BIT;
  if (ctx.accel_structures()) s |= VK_PIPELINE_STAGE_ACCELERATION_STRUCTURE_BUILD_BIT_KHR;
  return s;
}

void barrier(VkCommandBuffer cmd, VkPipelineStageFlags src_stages, VkAccessFlags src, VkPipelineStageFlags dst_stages,
             VkAccessFlags dst) {
  VkMemoryBarrier mb{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
  mb.srcAccessMask = src;
  mb.dstAccessMask = dst;
  vkCmdPipelineBarrier(cmd, src_stages, dst_stages, 0, 1, &mb, 0, nullptr, 0, nullptr);
}

} // namespace

void barrier_before_copy(const Context& ctx, VkCommandBuffer cmd) {
  VkAccessFlags src = VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT;
  if (ctx.accel_structures()) src |= VK_ACCESS_ACCELERATION_STRUCTURE_WRITE_BIT_KHR;
  barrier(cmd, device_stages(ctx), src, VK_PIPELINE_STAGE_TRANSFER_BIT,
          VK_ACCESS_TRANSFER_READ_BIT | VK_ACCESS_TRANSFER_WRITE_BIT);
}

void barrier_after_upload(const Context& ctx, VkCommandBuffer cmd) {
  barrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT, device_stages(ctx),
          VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_UNIFORM_READ_BIT |
              VK_ACCESS_TRANSFER_READ_BIT | VK_ACCESS_TRANSFER_WRITE_BIT);
}

void barrier_after_readback(const Context& ctx, VkCommandBuffer cmd) {
  barrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT,
          VK_PIPELINE_STAGE_HOST_BIT | device_stages(ctx), VK_ACCESS_HOST_READ_BIT);
}

void barrier_after_dispatch(VkCommandBuffer cmd) {
  barrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT,
          VK_PIPELINE_STAGE_HOST_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT | VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
          VK_ACCESS_HOST_READ_BIT | VK_ACCESS_TRANSFER_READ_BIT | VK_ACCESS_TRANSFER_WRITE_BIT |
              VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT);
}

void barrier_after_trace_rays(VkCommandBuffer cmd) {
  constexpr VkPipelineStageFlags rt = VK_PIPELINE_STAGE_RAY_TRACING_SHADER_BIT_KHR;
  barrier(cmd, rt, VK_ACCESS_SHADER_WRITE_BIT, VK_PIPELINE_STAGE_HOST_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT | rt,
          VK_ACCESS_HOST_READ_BIT | VK_ACCESS_TRANSFER_READ_BIT | VK_ACCESS_TRANSFER_WRITE_BIT |
              VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT);
}

void barrier_after_fill(VkCommandBuffer cmd) {
  barrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_RAY_TRACING_SHADER_BIT_KHR,
          VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT);
}

void barrier_after_accel_build(const Context& ctx, VkCommandBuffer cmd) {
  barrier(cmd, VK_PIPELINE_STAGE_ACCELERATION_STRUCTURE_BUILD_BIT_KHR, VK_ACCESS_ACCELERATION_STRUCTURE_WRITE_BIT_KHR,
          VK_PIPELINE_STAGE_ACCELERATION_STRUCTURE_BUILD_BIT_KHR | ctx.shader_stages(),
          VK_ACCESS_ACCELERATION_STRUCTURE_READ_BIT_KHR);
}

} // namespace masq::vk
