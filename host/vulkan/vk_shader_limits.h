// What a device says about running the kernels: the work-group size to dispatch with,
// and whether it can be told to keep IEEE infinities, NaN and signed zeros. Queried from
// the device, so every pipeline (compute traversal, ray query, bv tracer) fits it.
#pragma once
#include "host/vulkan/vk_context.h"
#include <cstdint>
#include <span>
#include <vector>

namespace masq::vk {

struct ShaderLimits {
  std::uint32_t subgroup_size = 1;          // VkPhysicalDeviceSubgroupProperties (Vulkan 1.1)
  std::uint32_t max_group_size_x = 1;       // maxComputeWorkGroupSize[0]
  std::uint32_t max_group_invocations = 1;  // maxComputeWorkGroupInvocations
  bool preserve_float32 = false;            // shaderSignedZeroInfNanPreserveFloat32 (Vulkan 1.2)
};

ShaderLimits shader_limits(const Context& ctx);

// The work-group size for `want` invocations (the kernels' preferred 64, or
// MASQ_VK_LOCAL_SIZE): rounded up to a multiple of the subgroup size, so no subgroup runs
// partly empty, then lowered to the device's limits (to a multiple of the subgroup size
// where the limit allows one).
std::uint32_t fit_local_size(const ShaderLimits& l, std::uint32_t want);

// The size the Vulkan pipelines dispatch with on this device: MASQ_VK_LOCAL_SIZE
// (1..1024, exact, for tuning: masq::Error if the device cannot run it) or 64 fitted
// by fit_local_size.
std::uint32_t local_size(const Context& ctx);

// The module as the device gets it (host/vulkan/spirv_float_controls.h): every float
// operation decorated NoContraction, on every device; SignedZeroInfNanPreserve where
// the device supports it. MASQ_VK_FLOAT_CONTROLS=off (an A/B switch for a driver
// suspected of mishandling them; the default is on) passes the module as glslang wrote
// it: the kernels' results may then differ in their last bits from the other backends'.
std::vector<std::uint32_t> device_spirv(const Context& ctx, std::span<const std::uint32_t> spirv);
// Whether MASQ_VK_FLOAT_CONTROLS (on|off, default on) asks for the patches above;
// throws masq::Error for another value.
bool float_controls_enabled();

} // namespace masq::vk
