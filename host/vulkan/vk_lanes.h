// The threads a Vulkan device keeps in flight, for Backend::fill_rays (host/device_fill.h).
#pragma once
#include "host/vulkan/vk_context.h"
#include <cstddef>

namespace masq::vk {

// Core Vulkan does not report compute units, so this reads what vendors expose:
// VK_NV_shader_sm_builtins (SMs x warps per SM x subgroup size), VK_AMD_shader_core_
// properties (engines x arrays x CUs x SIMDs x wavefronts per SIMD x wavefront size);
// a CPU device (lavapipe): its hardware threads x subgroup size. 0 when none of these
// applies (the device does not say).
std::size_t resident_threads(const Context& ctx);

} // namespace masq::vk
