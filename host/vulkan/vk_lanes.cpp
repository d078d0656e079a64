#include "host/vulkan/vk_lanes.h"
#include <algorithm>
#include <cstring>
#include <thread>
#include <vector>

namespace masq::vk {
namespace {

bool has_extension(VkPhysicalDevice dev, const char* name) {
  std::uint32_t n = 0;
  if (vkEnumerateDeviceExtensionProperties(dev, nullptr, &n, nullptr) != VK_SUCCESS) return false;
  std::vector<VkExtensionProperties> ext(n);
  if (vkEnumerateDeviceExtensionProperties(dev, nullptr, &n, ext.data()) != VK_SUCCESS) return false;
  for (const VkExtensionProperties& e : ext)
    if (std::strcmp(e.extensionName, name) == 0) return true;
  return false;
}

} // namespace

std::size_t resident_threads(const Context& ctx) {
  // Structures of extensions the device supports may be chained to a properties query
  // without enabling the extension.
  VkPhysicalDeviceSubgroupProperties subgroup{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SUBGROUP_PROPERTIES};
  VkPhysicalDeviceShaderSMBuiltinsPropertiesNV nv{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SHADER_SM_BUILTINS_PROPERTIES_NV};
  VkPhysicalDeviceShaderCorePropertiesAMD amd{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SHADER_CORE_PROPERTIES_AMD};
  const bool has_nv = has_extension(ctx.physical, VK_NV_SHADER_SM_BUILTINS_EXTENSION_NAME);
  const bool has_amd = has_extension(ctx.physical, VK_AMD_SHADER_CORE_PROPERTIES_EXTENSION_NAME);
  if (has_nv) subgroup.pNext = &nv;
  else if (has_amd) subgroup.pNext = &amd;
  VkPhysicalDeviceProperties2 props{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2};
  props.pNext = &subgroup;
  vkGetPhysicalDeviceProperties2(ctx.physical, &props);
  const std::size_t lanes = subgroup.subgroupSize == 0 ? 1 : subgroup.subgroupSize;
  if (has_nv) return std::size_t(nv.shaderSMCount) * nv.shaderWarpsPerSM * lanes;
  if (has_amd)
    return std::size_t(amd.shaderEngineCount) * amd.shaderArraysPerEngineCount * amd.computeUnitsPerShaderArray *
           amd.simdPerComputeUnit * amd.wavefrontsPerSimd * amd.wavefrontSize;
  if (ctx.props.deviceType == VK_PHYSICAL_DEVICE_TYPE_CPU)
    return std::size_t(std::max(1u, std::thread::hardware_concurrency())) * lanes;
  return 0;
}

} // namespace masq::vk
