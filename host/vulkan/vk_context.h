// The Vulkan instance, device and queue every Vulkan-based backend shares: Vulkan 1.2, on
// the device host/vulkan/vk_devices.h chooses (best-ranked, or the one MASQ_VK_DEVICE /
// MASQ_RQ_DEVICE / MASQ_RT_DEVICE names; rayquery and rtpipeline on the vulkan backend's
// device unless told otherwise).
// The loader honours VK_DRIVER_FILES / VK_ICD_FILENAMES from the environment.
#pragma once
#include "host/device_choice.h"
#include "host/vulkan/vk_check.h"
#include "host/vulkan/vk_owned.h"
#include "host/vulkan/vk_shared_objects.h"
#include <vulkan/vulkan.h>
#include <cstdint>
#include <atomic>
#include <memory>
#include <mutex>
#include <string>
#include <utility>

namespace masq::vk {

// How long submit_and_wait waits for one submission before it gives the device up:
// 600 s by default, lowered by MASQ_VK_WAIT_SECONDS (a positive integer).
inline constexpr std::uint64_t kDefaultWaitSeconds = 600;
std::uint64_t wait_limit_seconds();

class Staging;       // host/vulkan/vk_staging.h
class PipelineCache; // host/vulkan/vk_pipeline_cache.h

// Entry points of VK_KHR_acceleration_structure (not exported by the loader).
struct AccelFunctions {
  PFN_vkCreateAccelerationStructureKHR create = nullptr;
  PFN_vkDestroyAccelerationStructureKHR destroy = nullptr;
  PFN_vkGetAccelerationStructureBuildSizesKHR build_sizes = nullptr;
  PFN_vkCmdBuildAccelerationStructuresKHR cmd_build = nullptr;
  PFN_vkGetAccelerationStructureDeviceAddressKHR device_address = nullptr;
  PFN_vkCmdWriteAccelerationStructuresPropertiesKHR cmd_write_properties = nullptr; // compacted sizes
  PFN_vkCmdCopyAccelerationStructureKHR cmd_copy = nullptr;                         // compaction
};

// Entry points of VK_KHR_ray_tracing_pipeline.
struct RayPipelineFunctions {
  PFN_vkCreateRayTracingPipelinesKHR create = nullptr;
  PFN_vkGetRayTracingShaderGroupHandlesKHR group_handles = nullptr;
  PFN_vkCmdTraceRaysKHR cmd_trace = nullptr;
};

class Context {
 public:
  // One context per need (compute, ray query, ray-tracing pipeline), shared while any
  // backend holds it. `backend` names the caller in the BackendUnavailable message
  // ("vulkan: ...", "rayquery: ...").
  static std::shared_ptr<Context> get(const char* backend, DeviceNeed need = DeviceNeed::Compute);
  ~Context();
  Context(const Context&) = delete;
  Context& operator=(const Context&) = delete;

  // What the backends read; all of it is set once, by create().
  VkInstance instance() const { return instance_.get(); }
  VkPhysicalDevice physical() const { return physical_; }
  VkDevice device() const { return device_.get(); }
  std::uint32_t timestamp_valid_bits() const { return timestamp_valid_bits_; }
  const VkPhysicalDeviceProperties& props() const { return props_; }
  const VkPhysicalDeviceMemoryProperties& memory() const { return memory_; }
  bool ray_query() const { return ray_query_; }       // VK_KHR_ray_query enabled
  bool ray_pipeline() const { return ray_pipeline_; } // VK_KHR_ray_tracing_pipeline enabled
  // Driver acceleration structures (either of the two above): accel_props and accel are set.
  bool accel_structures() const { return ray_query_ || ray_pipeline_; }
  // The shader stages this context's pipelines run in (barriers name them).
  VkPipelineStageFlags shader_stages() const {
    return VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | (ray_pipeline_ ? VK_PIPELINE_STAGE_RAY_TRACING_SHADER_BIT_KHR : 0);
  }
  const VkPhysicalDeviceAccelerationStructurePropertiesKHR& accel_props() const { return accel_props_; }
  const AccelFunctions& accel() const { return accel_; }
  const VkPhysicalDeviceRayTracingPipelinePropertiesKHR& rt_props() const { return rt_props_; } // ray_pipeline only
  const RayPipelineFunctions& rt() const { return rt_; }

  // bufferDeviceAddress is enabled (always for ray query; for compute when the device
  // has it): scene arrays over one binding are then read by address.
  bool buffer_device_address() const { return buffer_device_address_; }
  // The largest buffer one allocation can hold: min(maxMemoryAllocationSize,
  // maxBufferSize where the device reports it), and which of the two it is.
  std::uint64_t max_allocation() const { return max_allocation_; }
  const char* max_allocation_name() const { return max_allocation_name_; }
  // Read once with the other properties, for the work-group size and the float-controls
  // patch of every pipeline (host/vulkan/vk_shader_limits.h).
  std::uint32_t subgroup_size() const { return subgroup_size_; } // VkPhysicalDeviceSubgroupProperties
  bool signed_zero_inf_nan_preserve_float32() const {            // VkPhysicalDeviceFloatControlsProperties
    return signed_zero_inf_nan_preserve_float32_;
  }
  // MASQ_VK_PIPELINE_STATS=1 and the device has VK_KHR_pipeline_executable_properties:
  // every compute pipeline's compile statistics (registers, spills, local memory, as
  // the driver names them) go to stderr (host/vulkan/vk_pipeline.cpp).
  bool pipeline_statistics() const { return pipeline_statistics_; }
  PFN_vkGetPipelineExecutablePropertiesKHR executable_properties() const { return executable_properties_; }
  PFN_vkGetPipelineExecutableStatisticsKHR executable_statistics() const { return executable_statistics_; }

  std::string device_name() const; // "llvmpipe (...) [Mesa 25.0.7 ...]"
  // Largest storage-buffer binding, after MASQ_VK_MAX_BINDING_BYTES (host/limit_knob.h).
  std::uint64_t max_storage_buffer_range() const;
  // Largest single array buffer, after MASQ_VK_MAX_ALLOCATION_BYTES.
  std::uint64_t max_allocation_bytes() const;
  // maxMemoryAllocationCount (4096 on many drivers) after MASQ_VK_MAX_ALLOCATIONS: the
  // device memory allocations this context may hold at once. vk::Buffer takes one per
  // buffer: acquire_allocation before vkAllocateMemory (throws masq::Error naming the
  // limit when all are live), held until after vkFreeMemory.
  std::uint64_t max_allocation_count() const;
  class Allocation {
   public:
    Allocation() = default;
    ~Allocation() { reset(); }
    Allocation(Allocation&& o) noexcept : ctx_(std::exchange(o.ctx_, nullptr)) {}
    Allocation& operator=(Allocation&& o) noexcept {
      if (this != &o) {
        reset();
        ctx_ = std::exchange(o.ctx_, nullptr);
      }
      return *this;
    }
    Allocation(const Allocation&) = delete;
    Allocation& operator=(const Allocation&) = delete;

   private:
    friend class Context;
    explicit Allocation(Context* ctx) : ctx_(ctx) {}
    void reset() noexcept {
      if (ctx_) ctx_->live_allocations_.fetch_sub(1);
      ctx_ = nullptr;
    }
    Context* ctx_ = nullptr;
  };
  [[nodiscard]] Allocation acquire_allocation();

  // One-shot command buffer: begin, record, then submit_and_wait (blocks, frees it).
  // Backends on several threads share this context's command pool and queue, which
  // Vulkan requires to be externally synchronised: begin_commands takes a lock that
  // submit_and_wait releases, so recording in between must not throw, and a thread
  // must not begin a second command buffer before submitting the first.
  VkCommandBuffer begin_commands();
  void submit_and_wait(VkCommandBuffer cmd);

  // VK_ERROR_DEVICE_LOST from a submission or its wait (the driver reset the device: a
  // dispatch past its watchdog, a faulting kernel) is one masq::Error naming the device,
  // and the context is marked lost: begin_commands then refuses at once instead of
  // submitting to a dead device, and Context::get opens a fresh context for the next
  // backend. MASQ_VK_FAULT_DEVICE_LOST=1 (tests) reports it after a real, finished wait.
  // A wait longer than wait_limit_seconds() is one masq::Error too, and marks the context
  // lost and hung (its in-flight work and device are left alone; MASQ_VK_FAULT_TIMEOUT=1
  // reports a timeout after a real, finished wait).
  bool lost() const { return lost_.load(); }

  // The persistent staging buffer every copy to or from unmapped device memory goes
  // through (created on first use), and the pipeline cache every vkCreateComputePipelines
  // uses (loaded from and saved to masq's cache directory).
  Staging& staging();
  VkPipelineCache pipeline_cache() const;
  // The pipeline layouts and pipelines every backend on this context shares
  // (host/vulkan/vk_shared_objects.h).
  SharedObjects& shared() { return *shared_; }
  const PipelineCache& pipeline_cache_file() const { return *pipeline_cache_; }

  // MASQ_VK_VALIDATION=1: VK_LAYER_KHRONOS_validation is enabled with a debug messenger
  // that prints every error and counts it; submit_and_wait then throws masq::Error
  // naming the first new error, so a test cannot pass over a validation error.
  // MASQ_VK_VALIDATION=sync also turns on synchronization validation.
  bool validation() const { return static_cast<bool>(messenger_); }
  // Validation errors reported by any context of this process.
  static std::uint64_t validation_error_count();

 private:
  Context() = default;
  void create(const char* backend, DeviceNeed need);
  void check_validation();
  // Declared in the order they are made, so each goes before what made it; the staging
  // buffer and the pipeline cache, declared last, go before the device.
  Owned<VkInstance> instance_{vkDestroyInstance};
  Owned<VkDebugUtilsMessengerEXT, VkInstance> messenger_;
  Owned<VkDevice> device_{vkDestroyDevice};
  DeviceOwned<VkCommandPool> command_pool_;
  VkPhysicalDevice physical_ = VK_NULL_HANDLE;
  VkQueue queue_ = VK_NULL_HANDLE;
  std::uint32_t queue_family_ = 0;
  std::uint32_t timestamp_valid_bits_ = 0;
  VkPhysicalDeviceProperties props_{};
  VkPhysicalDeviceMemoryProperties memory_{};
  bool ray_query_ = false;
  bool ray_pipeline_ = false;
  VkPhysicalDeviceAccelerationStructurePropertiesKHR accel_props_{};
  AccelFunctions accel_;
  VkPhysicalDeviceRayTracingPipelinePropertiesKHR rt_props_{};
  RayPipelineFunctions rt_;
  bool buffer_device_address_ = false;
  std::uint64_t max_allocation_ = 0;
  const char* max_allocation_name_ = "maxMemoryAllocationSize";
  std::uint32_t subgroup_size_ = 1;
  bool signed_zero_inf_nan_preserve_float32_ = false;
  bool pipeline_statistics_ = false;
  PFN_vkGetPipelineExecutablePropertiesKHR executable_properties_ = nullptr;
  PFN_vkGetPipelineExecutableStatisticsKHR executable_statistics_ = nullptr;
  std::string driver_info_;
  std::mutex submit_mutex_;
  std::uint64_t validation_errors_seen_ = 0;
  std::atomic<std::uint64_t> live_allocations_{0};
  std::atomic<bool> lost_{false};
  std::atomic<bool> hung_{false}; // a wait timed out: the device may still be running it
  [[noreturn]] void throw_device_lost(const char* call);
  std::mutex staging_mutex_;
  std::unique_ptr<PipelineCache> pipeline_cache_; // saved and destroyed before the device
  std::unique_ptr<Staging> staging_;              // destroyed before the device
  std::unique_ptr<SharedObjects> shared_ = std::make_unique<SharedObjects>(); // destroyed first
};

} // namespace masq::vk
