// The Vulkan physical devices as masq sees them: each one described as a DeviceInfo
// (host/device_choice.h: type, why it cannot run the compute kernels, ray query or the
// ray-tracing pipeline, memory, subgroup size), the choice of the vulkan, rayquery and
// rtpipeline backends' device, and the listing `masq info` prints.
#pragma once
#include "host/device_choice.h"
#include <vulkan/vulkan.h>
#include <cstdint>
#include <vector>

namespace masq::vk {

// The device extensions the rayquery backend enables.
inline const char* const kRayQueryExtensions[] = {
    VK_KHR_ACCELERATION_STRUCTURE_EXTENSION_NAME,
    VK_KHR_RAY_QUERY_EXTENSION_NAME,
    VK_KHR_DEFERRED_HOST_OPERATIONS_EXTENSION_NAME,
};
// The device extensions the rtpipeline backend enables.
inline const char* const kRayPipelineExtensions[] = {
    VK_KHR_ACCELERATION_STRUCTURE_EXTENSION_NAME,
    VK_KHR_RAY_TRACING_PIPELINE_EXTENSION_NAME,
    VK_KHR_DEFERRED_HOST_OPERATIONS_EXTENSION_NAME,
};
// What the rtpipeline backend's shaders need of VkPhysicalDeviceRayTracingPipelinePropertiesKHR:
// one level of traceRayEXT (from the ray-generation shader), the procedural hit's
// attributes (kernels/rt_payload.h: 6 words), and a hit record's stride (a group handle
// and the record's data, kernels/rt_payload.h).
inline constexpr std::uint32_t kRtRecursionDepth = 1;
inline constexpr std::uint32_t kRtHitAttributeBytes = 24;
inline constexpr std::uint32_t kRtRecordDataBytes = 16;

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

// The device the vulkan (need Compute), rayquery (RayQuery) or rtpipeline (RayPipeline)
// backend opens: by the selectors in force (device_selector). Throws masq::Error for a
// selector that names no device and BackendUnavailable "<backend>: <why>" when no named
// device serves.
const PhysicalDevice& choose_physical_device(const std::vector<PhysicalDevice>& devices, const char* backend,
                                             DeviceNeed need);

// The choice of the backend with that need among `devices`, by the selectors in force
// (device_selector). Throws masq::Error for a selector naming none.
DeviceChoice choose_vulkan_device(const std::vector<DeviceInfo>& devices, DeviceNeed need);

// For `masq info`: every Vulkan device, from an instance of its own (no validation layer).
// Throws BackendUnavailable when there is no Vulkan driver.
std::vector<DeviceInfo> vulkan_device_infos();

} // namespace masq::vk
