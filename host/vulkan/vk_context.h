// The Vulkan instance, device and queue every Vulkan-based backend shares: Vulkan 1.2, on
// the device host/vulkan/vk_devices.h chooses (best-ranked, or the one MASQ_VK_DEVICE /
// MASQ_RQ_DEVICE names; rayquery on the vulkan backend's device unless told otherwise).
// The loader honours VK_DRIVER_FILES / VK_ICD_FILENAMES from the environment.
#pragma once
#include "host/vulkan/vk_check.h"
#include <vulkan/vulkan.h>
#include <cstdint>
#include <atomic>
#include <memory>
#include <mutex>
#include <string>

namespace masq::vk {

// Entry points of VK_KHR_acceleration_structure (not exported by the loader).
struct AccelFunctions {
  PFN_vkCreateAccelerationStructureKHR create = nullptr;
  PFN_vkDestroyAccelerationStructureKHR destroy = nullptr;
  PFN_vkGetAccelerationStructureBuildSizesKHR build_sizes = nullptr;
  PFN_vkCmdBuildAccelerationStructuresKHR cmd_build = nullptr;
  PFN_vkGetAccelerationStructureDeviceAddressKHR device_address = nullptr;
};

class Context {
 public:
  // One context per kind, shared while any backend holds it. `backend` names the
  // caller in the BackendUnavailable message ("vulkan: ...", "rayquery: ...").
  static std::shared_ptr<Context> get(const char* backend, bool ray_query);
  ~Context();
  Context(const Context&) = delete;
  Context& operator=(const Context&) = delete;

  VkInstance instance = VK_NULL_HANDLE;
  VkPhysicalDevice physical = VK_NULL_HANDLE;
  VkDevice device = VK_NULL_HANDLE;
  VkQueue queue = VK_NULL_HANDLE;
  std::uint32_t queue_family = 0;
  std::uint32_t timestamp_valid_bits = 0;
  VkCommandPool command_pool = VK_NULL_HANDLE;
  VkPhysicalDeviceProperties props{};
  VkPhysicalDeviceMemoryProperties memory{};
  bool ray_query = false;
  VkPhysicalDeviceAccelerationStructurePropertiesKHR accel_props{};
  AccelFunctions accel;

  // bufferDeviceAddress is enabled (always for ray query; for compute when the device
  // has it): scene arrays over one binding are then read by address.
  bool buffer_device_address = false;
  // The largest buffer one allocation can hold: min(maxMemoryAllocationSize,
  // maxBufferSize where the device reports it), and which of the two it is.
  std::uint64_t max_allocation = 0;
  const char* max_allocation_name = "maxMemoryAllocationSize";

  std::string device_name() const; // "llvmpipe (...) [Mesa 25.0.7 ...]"
  // Largest storage-buffer binding, after MASQ_VK_MAX_BINDING_BYTES and the test
  // override (host/limit_knob.h, vulkan_backends.h).
  std::uint64_t max_storage_buffer_range() const;
  // Largest single array buffer, after MASQ_VK_MAX_ALLOCATION_BYTES and the override.
  std::uint64_t max_allocation_bytes() const;

  // One-shot command buffer: begin, record, then submit_and_wait (blocks, frees it).
  // Backends on several threads share this context's command pool and queue, which
  // Vulkan requires to be externally synchronised: begin_commands takes a lock that
  // submit_and_wait releases, so recording in between must not throw, and a thread
  // must not begin a second command buffer before submitting the first.
  VkCommandBuffer begin_commands();
  void submit_and_wait(VkCommandBuffer cmd);

  // MASQ_VK_VALIDATION=1: VK_LAYER_KHRONOS_validation is enabled with a debug messenger
  // that prints every error and counts it; submit_and_wait then throws masq::Error
  // naming the first new error, so a test cannot pass over a validation error.
  bool validation() const { return messenger_ != VK_NULL_HANDLE; }
  // Validation errors reported by any context of this process.
  static std::uint64_t validation_error_count();

 private:
  Context() = default;
  void create(const char* backend, bool want_ray_query);
  void enable_validation(VkInstanceCreateInfo& ici);
  void check_validation();
  std::string driver_info_;
  std::mutex submit_mutex_;
  VkDebugUtilsMessengerEXT messenger_ = VK_NULL_HANDLE;
  std::uint64_t validation_errors_seen_ = 0;
};

} // namespace masq::vk
