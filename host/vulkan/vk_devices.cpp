#include "host/vulkan/vk_devices.h"
#include "host/backend.h"
#include "host/vulkan/vk_check.h"
#include "masq/knobs.h"
#include "host/vulkan/vk_owned.h"
#include <fmt/format.h>
#include <cstdlib>
#include <cstring>
#include <string>

namespace masq::vk {

namespace {

// Fault injection for tests (tests/test_device_faults.cpp): MASQ_VK_HIDE_EXTENSIONS.
bool hidden_extension(const char* name) {
  const std::optional<std::string> hide = knob_text(Knob::VkHideExtensions);
  if (!hide) return false;
  std::string list = "," + *hide + ",";
  return list.find(std::string(",") + name + ",") != std::string::npos;
}

std::vector<VkExtensionProperties> device_extensions(VkPhysicalDevice pd) {
  std::uint32_t n = 0;
  vkEnumerateDeviceExtensionProperties(pd, nullptr, &n, nullptr);
  std::vector<VkExtensionProperties> exts(n);
  vkEnumerateDeviceExtensionProperties(pd, nullptr, &n, exts.data());
  exts.resize(n);
  return exts;
}

bool has_extension(const std::vector<VkExtensionProperties>& exts, const char* name) {
  if (hidden_extension(name)) return false;
  for (const auto& e : exts)
    if (std::strcmp(e.extensionName, name) == 0) return true;
  return false;
}

int compute_queue_family(VkPhysicalDevice pd) {
  std::uint32_t n = 0;
  vkGetPhysicalDeviceQueueFamilyProperties(pd, &n, nullptr);
  std::vector<VkQueueFamilyProperties> fams(n);
  vkGetPhysicalDeviceQueueFamilyProperties(pd, &n, fams.data());
  for (std::uint32_t i = 0; i < n; ++i)
    if (fams[i].queueFlags & VK_QUEUE_COMPUTE_BIT) return static_cast<int>(i);
  return -1;
}

// Why this device cannot serve ray query, or "" when it can. Features are asked only
// after their extensions are known to be there.
std::string ray_query_gap(VkPhysicalDevice pd, const std::vector<VkExtensionProperties>& exts) {
  for (const char* e : kRayQueryExtensions)
    if (!has_extension(exts, e)) return fmt::format("lacks {}", e);
  VkPhysicalDeviceRayQueryFeaturesKHR rq{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_RAY_QUERY_FEATURES_KHR};
  VkPhysicalDeviceAccelerationStructureFeaturesKHR as{
      VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_ACCELERATION_STRUCTURE_FEATURES_KHR, &rq};
  VkPhysicalDeviceVulkan12Features v12{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES, &as};
  VkPhysicalDeviceFeatures2 f2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2, &v12};
  vkGetPhysicalDeviceFeatures2(pd, &f2);
  if (!rq.rayQuery) return "lacks the rayQuery feature";
  if (!as.accelerationStructure) return "lacks the accelerationStructure feature";
  if (!v12.bufferDeviceAddress) return "lacks the bufferDeviceAddress feature";
  return "";
}

// Why this device cannot serve the rtpipeline backend, or "" when it can: its extensions,
// features, and the properties its shaders and binding table need (vk_devices.h).
// masq traces with vkCmdTraceRaysKHR, so rayTracingPipelineTraceRaysIndirect is not needed.
std::string ray_pipeline_gap(VkPhysicalDevice pd, const std::vector<VkExtensionProperties>& exts) {
  for (const char* e : kRayPipelineExtensions)
    if (!has_extension(exts, e)) return fmt::format("lacks {}", e);
  VkPhysicalDeviceRayTracingPipelineFeaturesKHR rt{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_RAY_TRACING_PIPELINE_FEATURES_KHR};
  VkPhysicalDeviceAccelerationStructureFeaturesKHR as{
      VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_ACCELERATION_STRUCTURE_FEATURES_KHR, &rt};
  VkPhysicalDeviceVulkan12Features v12{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES, &as};
  VkPhysicalDeviceFeatures2 f2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2, &v12};
  vkGetPhysicalDeviceFeatures2(pd, &f2);
  if (!rt.rayTracingPipeline) return "lacks the rayTracingPipeline feature";
  if (!as.accelerationStructure) return "lacks the accelerationStructure feature";
  if (!v12.bufferDeviceAddress) return "lacks the bufferDeviceAddress feature";
  VkPhysicalDeviceRayTracingPipelinePropertiesKHR p{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_RAY_TRACING_PIPELINE_PROPERTIES_KHR};
  VkPhysicalDeviceProperties2 p2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2, &p};
  vkGetPhysicalDeviceProperties2(pd, &p2);
  if (p.maxRayRecursionDepth < kRtRecursionDepth)
    return fmt::format("has maxRayRecursionDepth {} (masq needs {})", p.maxRayRecursionDepth, kRtRecursionDepth);
  if (p.maxRayHitAttributeSize < kRtHitAttributeBytes)
    return fmt::format("has maxRayHitAttributeSize {} (masq's hit attributes take {} bytes)", p.maxRayHitAttributeSize,
                       kRtHitAttributeBytes);
  if (p.maxShaderGroupStride < p.shaderGroupHandleSize + kRtRecordDataBytes)
    return fmt::format("has maxShaderGroupStride {} (a hit record takes a {}-byte handle and {} bytes of data)",
                       p.maxShaderGroupStride, p.shaderGroupHandleSize, kRtRecordDataBytes);
  return "";
}

DeviceType device_type(VkPhysicalDeviceType t) {
  switch (t) {
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU: return DeviceType::Discrete;
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU: return DeviceType::Integrated;
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU: return DeviceType::Virtual;
    case VK_PHYSICAL_DEVICE_TYPE_CPU: return DeviceType::Cpu;
    default: return DeviceType::Other;
  }
}

std::uint64_t largest_device_local_heap(VkPhysicalDevice pd) {
  VkPhysicalDeviceMemoryProperties mem{};
  vkGetPhysicalDeviceMemoryProperties(pd, &mem);
  std::uint64_t best = 0;
  for (std::uint32_t i = 0; i < mem.memoryHeapCount; ++i)
    if (mem.memoryHeaps[i].flags & VK_MEMORY_HEAP_DEVICE_LOCAL_BIT) best = std::max(best, mem.memoryHeaps[i].size);
  return best;
}

DeviceInfo describe(VkPhysicalDevice pd, int index, int family) {
  VkPhysicalDeviceProperties p{};
  vkGetPhysicalDeviceProperties(pd, &p);
  DeviceInfo d;
  d.index = index;
  d.name = p.deviceName;
  d.type = device_type(p.deviceType);
  if (family < 0) d.unusable = "has no compute queue";
  else if (p.apiVersion < VK_API_VERSION_1_2) d.unusable = "is older than Vulkan 1.2";
  const auto exts = device_extensions(pd);
  d.no_ray_query = ray_query_gap(pd, exts);
  d.no_ray_pipeline = ray_pipeline_gap(pd, exts);
  d.memory_bytes = largest_device_local_heap(pd);
  // Subgroup properties are core in 1.1, driver properties in 1.2: chained only where the
  // device reports that version.
  VkPhysicalDeviceSubgroupProperties sub{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SUBGROUP_PROPERTIES};
  VkPhysicalDeviceDriverProperties drv{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_DRIVER_PROPERTIES};
  if (p.apiVersion >= VK_API_VERSION_1_1) {
    if (p.apiVersion >= VK_API_VERSION_1_2) sub.pNext = &drv;
    VkPhysicalDeviceProperties2 p2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2, &sub};
    vkGetPhysicalDeviceProperties2(pd, &p2);
    d.subgroup_size = sub.subgroupSize;
    d.subgroup_source = "VkPhysicalDeviceSubgroupProperties::subgroupSize";
  } else {
    d.subgroup_source = "none before Vulkan 1.1";
  }
  d.driver = p.apiVersion >= VK_API_VERSION_1_2
                 ? fmt::format("{} {}", drv.driverName, drv.driverInfo)
                 : fmt::format("driverVersion {:#x}", p.driverVersion);
  return d;
}

std::vector<DeviceInfo> infos(const std::vector<PhysicalDevice>& devices) {
  std::vector<DeviceInfo> out;
  for (const PhysicalDevice& d : devices) out.push_back(d.info);
  return out;
}

} // namespace

DeviceChoice choose_vulkan_device(const std::vector<DeviceInfo>& devices, DeviceNeed need) {
  const DeviceSelector vulkan = device_selector(DeviceApi::Vulkan);
  switch (need) {
    case DeviceNeed::Compute: return choose_device(devices, vulkan, "Vulkan", DeviceNeed::Compute);
    case DeviceNeed::RayQuery:
      return choose_traversal_device(devices, vulkan, device_selector(DeviceApi::RayQuery), need, DeviceApi::RayQuery);
    case DeviceNeed::RayPipeline:
      return choose_traversal_device(devices, vulkan, device_selector(DeviceApi::RtPipeline), need,
                                     DeviceApi::RtPipeline);
  }
  return {};
}

std::vector<PhysicalDevice> physical_devices(VkInstance instance) {
  std::uint32_t n = 0;
  vkEnumeratePhysicalDevices(instance, &n, nullptr);
  std::vector<VkPhysicalDevice> handles(n);
  vkEnumeratePhysicalDevices(instance, &n, handles.data());
  handles.resize(n);
  std::vector<PhysicalDevice> out;
  for (std::size_t i = 0; i < handles.size(); ++i) {
    int family = compute_queue_family(handles[i]);
    out.push_back({handles[i], family, describe(handles[i], static_cast<int>(i), family)});
  }
  return out;
}

const PhysicalDevice& choose_physical_device(const std::vector<PhysicalDevice>& devices, const char* backend,
                                             DeviceNeed need) {
  DeviceChoice c = choose_vulkan_device(infos(devices), need);
  if (c.position < 0) throw BackendUnavailable(fmt::format("{}: {}", backend, c.why));
  return devices[static_cast<std::size_t>(c.position)];
}

std::vector<DeviceInfo> vulkan_device_infos() {
  VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
  app.pApplicationName = "masq info";
  app.apiVersion = VK_API_VERSION_1_2;
  VkInstanceCreateInfo ici{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
  ici.pApplicationInfo = &app;
  Owned<VkInstance> instance(vkDestroyInstance);
  VkResult r = vkCreateInstance(&ici, nullptr, instance.put());
  if (r != VK_SUCCESS) {
    instance.release();
    throw BackendUnavailable(fmt::format("vulkan: no Vulkan driver (vkCreateInstance: {})", result_name(r)));
  }
  return infos(physical_devices(instance.get()));
}

bool device_has_extension(VkPhysicalDevice pd, const char* name) {
  return has_extension(device_extensions(pd), name);
}

} // namespace masq::vk
