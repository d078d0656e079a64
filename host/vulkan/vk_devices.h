// The Vulkan physical devices as masq sees them: each one described as a DeviceInfo
// (host/device_choice.h: type, why it cannot run the compute kernels or ray query,
// memory, subgroup size, ray-tracing pipeline), the choice of the vulkan and rayquery
// backends' device, and the listing `masq info` prints.
#pragma once
#include "host/device_choice.h"
#include <vulkan/vulkan.h>
#include <vector>

namespace masq::vk {

// The device extensions the rayquery backend enables.
inline const char* const kRayQueryExtensions[] = {
    VK_KHR_ACCELERATION_STRUCTURE_EXTENSION_NAME,
    VK_KHR_RAY_QUERY_EXTENSION_NAME,
    VK_KHR_DEFERRED_HOST_OPERATIONS_EXTENSION_NAME,
};

struct PhysicalDevice {
  VkPhysicalDevice handle = VK_NULL_HANDLE;
  int compute_family = -1; // the first queue family with compute, -1: none
  DeviceInfo info;
};

// Whether `pd` has device extension `name` (false for one MASQ_VK_HIDE_EXTENSIONS hides).
bool device_has_extension(VkPhysicalDevice pd, const char* name);

// Every physical device of `instance`, in enumeration order (info.index = position).
// MASQ_VK_HIDE_EXTENSIONS="VK_KHR_ray_query,..." makes the named device extensions look
// absent, so the missing-extension path runs on a driver that has them.
std::vector<PhysicalDevice> physical_devices(VkInstance instance);

// The device the vulkan (ray_query false) or rayquery backend opens: by the selectors in
// force (device_selector). Throws masq::Error for a selector that names no device and
// BackendUnavailable "<backend>: <why>" when no named device serves.
const PhysicalDevice& choose_physical_device(const std::vector<PhysicalDevice>& devices, const char* backend,
                                             bool ray_query);

// The choice of the vulkan (ray_query false) or rayquery backend among `devices`, by the
// selectors in force (device_selector). Throws masq::Error for a selector naming none.
DeviceChoice choose_vulkan_device(const std::vector<DeviceInfo>& devices, bool ray_query);

// For `masq info`: every Vulkan device, from an instance of its own (no validation layer).
// Throws BackendUnavailable when there is no Vulkan driver.
std::vector<DeviceInfo> vulkan_device_infos();

} // namespace masq::vk
