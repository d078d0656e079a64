#include "host/vulkan/vk_shader_limits.h"
#include "host/limit_knob.h"
#include "host/vulkan/spirv_float_controls.h"
#include "masq/error.h"
#include <algorithm>
#include <cstdlib>
#include <string>

namespace masq::vk {

namespace {

// 64 invocations: measured best on lavapipe (docs/results.md), and a multiple of every
// GPU's subgroup (8..64), so a GPU keeps it too.
constexpr std::uint32_t kPreferredLocalSize = 64;

// MASQ_VK_LOCAL_SIZE, or 0 when unset.
std::uint32_t local_size_override() {
  static const std::uint32_t size = [] {
    return std::uint32_t(knob_integer(Knob::VkLocalSize, "vulkan").value_or(0));
  }();
  return size;
}

} // namespace

ShaderLimits shader_limits(const Context& ctx) {
  ShaderLimits l;
  l.subgroup_size = ctx.subgroup_size();
  l.max_group_size_x = ctx.props().limits.maxComputeWorkGroupSize[0];
  l.max_group_invocations = ctx.props().limits.maxComputeWorkGroupInvocations;
  l.preserve_float32 = ctx.signed_zero_inf_nan_preserve_float32();
  return l;
}

std::uint32_t fit_local_size(const ShaderLimits& l, std::uint32_t want) {
  const std::uint32_t sub = l.subgroup_size > 0 ? l.subgroup_size : 1;
  const std::uint32_t limit = std::max(1u, std::min(l.max_group_size_x, l.max_group_invocations));
  std::uint32_t size = (std::max(want, 1u) + sub - 1) / sub * sub;
  if (size > limit) size = limit >= sub ? limit / sub * sub : limit;
  return size;
}

std::uint32_t local_size(const Context& ctx) {
  const ShaderLimits l = shader_limits(ctx);
  const std::uint32_t forced = local_size_override();
  if (forced == 0) return fit_local_size(l, kPreferredLocalSize);
  if (forced > l.max_group_size_x || forced > l.max_group_invocations)
    throw Error("vulkan: MASQ_VK_LOCAL_SIZE=" + std::to_string(forced) + " exceeds the device's work-group limits (" +
                "maxComputeWorkGroupSize[0] " + std::to_string(l.max_group_size_x) +
                ", maxComputeWorkGroupInvocations " + std::to_string(l.max_group_invocations) + ")");
  return forced;
}

bool float_controls_enabled() { return choice_knob("vulkan", Knob::VkFloatControls, "on"); }

std::vector<std::uint32_t> device_spirv(const Context& ctx, std::span<const std::uint32_t> spirv) {
  if (!float_controls_enabled()) return {spirv.begin(), spirv.end()};
  std::vector<std::uint32_t> exact = with_no_contraction(spirv);
  if (!shader_limits(ctx).preserve_float32) return exact;
  return with_signed_zero_inf_nan_preserve(exact);
}

} // namespace masq::vk
