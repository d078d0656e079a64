#include "host/vulkan/vk_lanes.h"
#include "host/vulkan/vk_devices.h"
#include <algorithm>
#include <thread>

namespace masq::vk {

std::size_t resident_threads(const Context& ctx) {
  // Structures of extensions the device supports may be chained to a properties query
  // without enabling the extension.
  VkPhysicalDeviceShaderSMBuiltinsPropertiesNV nv{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SHADER_SM_BUILTINS_PROPERTIES_NV};
  VkPhysicalDeviceShaderCorePropertiesAMD amd{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SHADER_CORE_PROPERTIES_AMD};
  const bool has_nv = device_has_extension(ctx.physical(), VK_NV_SHADER_SM_BUILTINS_EXTENSION_NAME);
  const bool has_amd = device_has_extension(ctx.physical(), VK_AMD_SHADER_CORE_PROPERTIES_EXTENSION_NAME);
  if (has_nv || has_amd) {
    VkPhysicalDeviceProperties2 props{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2};
    props.pNext = has_nv ? static_cast<void*>(&nv) : static_cast<void*>(&amd);
    vkGetPhysicalDeviceProperties2(ctx.physical(), &props);
  }
  const std::size_t lanes = ctx.subgroup_size();
  if (has_nv) return std::size_t(nv.shaderSMCount) * nv.shaderWarpsPerSM * lanes;
  if (has_amd)
    return std::size_t(amd.shaderEngineCount) * amd.shaderArraysPerEngineCount * amd.computeUnitsPerShaderArray *
           amd.simdPerComputeUnit * amd.wavefrontsPerSimd * amd.wavefrontSize;
  if (ctx.props().deviceType == VK_PHYSICAL_DEVICE_TYPE_CPU)
    return std::size_t(std::max(1u, std::thread::hardware_concurrency())) * lanes;
  return 0;
}

} // namespace masq::vk
