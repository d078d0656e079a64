#include "host/vulkan/vk_context.h"
#include "host/backend.h"
#include "host/limit_knob.h"
#include "host/vulkan/vk_devices.h"
#include "host/vulkan/vk_pipeline_cache.h"
#include "host/vulkan/vk_staging.h"
#include "host/vulkan/vulkan_backends.h"
#include <fmt/format.h>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <mutex>
#include <string>
#include <tuple>
#include <vector>

namespace masq::vk {

namespace {

bool env_is_one(Knob knob) { return knob_flag(knob, "vulkan"); }

} // namespace

std::uint64_t wait_limit_seconds() { return lowered_limit("vulkan", kDefaultWaitSeconds, Knob::VkWaitSeconds); }

namespace {

std::mutex g_mutex;
// Open contexts, shared by the backends that need the same device: keyed by the need and
// the selectors in force when they opened, so a backend opened with another selector
// (a Context naming its device) gets that device, not the one already open.
using ContextKey = std::tuple<int, std::string, std::string>; // need, vulkan selector, own selector
std::map<ContextKey, std::weak_ptr<Context>> g_contexts;

ContextKey context_key(DeviceNeed need) {
  const std::string vulkan = device_selector(DeviceApi::Vulkan).value;
  switch (need) {
    case DeviceNeed::Compute: return {static_cast<int>(need), vulkan, ""};
    case DeviceNeed::RayQuery: return {static_cast<int>(need), vulkan, device_selector(DeviceApi::RayQuery).value};
    case DeviceNeed::RayPipeline:
      return {static_cast<int>(need), vulkan, device_selector(DeviceApi::RtPipeline).value};
  }
  return {static_cast<int>(need), vulkan, ""};
}

constexpr const char* kValidationLayer = "VK_LAYER_KHRONOS_validation";
std::atomic<std::uint64_t> g_validation_errors{0};
std::mutex g_last_error_mutex;
std::string g_last_error; // the latest validation error's message, for the exception

VKAPI_ATTR VkBool32 VKAPI_CALL on_validation_message(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                                     VkDebugUtilsMessageTypeFlagsEXT,
                                                     const VkDebugUtilsMessengerCallbackDataEXT* data, void*) {
  const char* msg = data && data->pMessage ? data->pMessage : "(no message)";
  if (severity & VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT) {
    std::fprintf(stderr, "vulkan validation error: %s\n", msg);
    std::lock_guard<std::mutex> lock(g_last_error_mutex);
    g_last_error = msg;
    g_validation_errors.fetch_add(1);
  } else {
    std::fprintf(stderr, "vulkan validation warning: %s\n", msg);
  }
  return VK_FALSE; // never abort the call: the error is reported at the next submission
}

bool validation_requested() { return knob_choice(Knob::VkValidation, "vulkan") != "0"; }

// MASQ_VK_VALIDATION=sync adds the layer's synchronization validation (hazards between
// transfers, shaders and acceleration-structure builds inside a command buffer), asked
// for through VK_EXT_validation_features, which the layer itself provides.
bool sync_validation_requested() { return knob_choice(Knob::VkValidation, "vulkan") == "sync"; }

bool layer_has_extension(const char* layer, const char* extension) {
  std::uint32_t n = 0;
  vkEnumerateInstanceExtensionProperties(layer, &n, nullptr);
  std::vector<VkExtensionProperties> exts(n);
  vkEnumerateInstanceExtensionProperties(layer, &n, exts.data());
  for (const auto& e : exts)
    if (std::strcmp(e.extensionName, extension) == 0) return true;
  return false;
}

bool instance_has_layer(const char* name) {
  std::uint32_t n = 0;
  vkEnumerateInstanceLayerProperties(&n, nullptr);
  std::vector<VkLayerProperties> layers(n);
  vkEnumerateInstanceLayerProperties(&n, layers.data());
  for (const auto& l : layers)
    if (std::strcmp(l.layerName, name) == 0) return true;
  return false;
}

} // namespace

std::shared_ptr<Context> Context::get(const char* backend, DeviceNeed need) {
  std::lock_guard<std::mutex> lock(g_mutex);
  std::weak_ptr<Context>& slot = g_contexts[context_key(need)];
  if (auto existing = slot.lock(); existing && !existing->lost()) return existing;
  std::shared_ptr<Context> ctx(new Context());
  ctx->create(backend, need);
  slot = ctx;
  return ctx;
}

void Context::create(const char* backend, DeviceNeed need) {
  const bool want_ray_query = need == DeviceNeed::RayQuery;
  const bool want_ray_pipeline = need == DeviceNeed::RayPipeline;
  const bool want_structures = want_ray_query || want_ray_pipeline;
  auto unavailable = [&](const std::string& why) {
    throw BackendUnavailable(fmt::format("{}: {}", backend, why));
  };
  VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
  app.pApplicationName = "masq";
  app.apiVersion = VK_API_VERSION_1_2;
  VkInstanceCreateInfo ici{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
  ici.pApplicationInfo = &app;
  VkDebugUtilsMessengerCreateInfoEXT mci{VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT};
  mci.messageSeverity = VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT;
  mci.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT;
  mci.pfnUserCallback = on_validation_message;
  const char* const layers[] = {kValidationLayer};
  const char* const extensions[] = {VK_EXT_DEBUG_UTILS_EXTENSION_NAME, VK_EXT_VALIDATION_FEATURES_EXTENSION_NAME};
  const bool validate = validation_requested();
  const bool validate_sync = sync_validation_requested();
  const VkValidationFeatureEnableEXT sync_feature = VK_VALIDATION_FEATURE_ENABLE_SYNCHRONIZATION_VALIDATION_EXT;
  VkValidationFeaturesEXT features{VK_STRUCTURE_TYPE_VALIDATION_FEATURES_EXT};
  features.enabledValidationFeatureCount = 1;
  features.pEnabledValidationFeatures = &sync_feature;
  if (validate) {
    // A missing layer is an error, not a silent run without checks.
    if (!instance_has_layer(kValidationLayer))
      unavailable(fmt::format("MASQ_VK_VALIDATION is set but the layer {} is not installed "
                              "(Debian: vulkan-validationlayers)", kValidationLayer));
    if (validate_sync && !layer_has_extension(kValidationLayer, VK_EXT_VALIDATION_FEATURES_EXTENSION_NAME))
      unavailable(fmt::format("MASQ_VK_VALIDATION=sync: the layer {} lacks {}", kValidationLayer,
                              VK_EXT_VALIDATION_FEATURES_EXTENSION_NAME));
    ici.enabledLayerCount = 1;
    ici.ppEnabledLayerNames = layers;
    ici.enabledExtensionCount = validate_sync ? 2 : 1;
    ici.ppEnabledExtensionNames = extensions;
    ici.pNext = &mci; // also reports errors of vkCreateInstance/vkDestroyInstance
    if (validate_sync) { // ahead of mci, which vkCreateDebugUtilsMessengerEXT takes alone
      features.pNext = &mci;
      ici.pNext = &features;
    }
  }
  VkResult r = vkCreateInstance(&ici, nullptr, instance_.put());
  if (r != VK_SUCCESS) {
    instance_.release();
    unavailable(fmt::format("no Vulkan driver (vkCreateInstance: {})", result_name(r)));
  }
  if (validate) {
    auto create_messenger = reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(
        vkGetInstanceProcAddr(instance_.get(), "vkCreateDebugUtilsMessengerEXT"));
    if (!create_messenger) unavailable("MASQ_VK_VALIDATION: no vkCreateDebugUtilsMessengerEXT");
    auto destroy_messenger = reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
        vkGetInstanceProcAddr(instance_.get(), "vkDestroyDebugUtilsMessengerEXT"));
    messenger_ = {instance_.get(), destroy_messenger};
    MASQ_VK_CHECK(create_messenger(instance_.get(), &mci, nullptr, messenger_.put()));
    validation_errors_seen_ = g_validation_errors.load();
  }

  // The device: the best-ranked one, or the one MASQ_VK_DEVICE / MASQ_RQ_DEVICE /
  // MASQ_RT_DEVICE / --device names; rayquery and rtpipeline take the vulkan backend's
  // device unless told otherwise (host/vulkan/vk_devices.h, host/device_choice.h).
  const std::vector<PhysicalDevice> devices = physical_devices(instance_.get());
  const PhysicalDevice& chosen = choose_physical_device(devices, backend, need);
  physical_ = chosen.handle;
  vkGetPhysicalDeviceProperties(physical_, &props_);
  queue_family_ = static_cast<std::uint32_t>(chosen.compute_family);
  vkGetPhysicalDeviceMemoryProperties(physical_, &memory_);
  {
    std::uint32_t nf = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(physical_, &nf, nullptr);
    std::vector<VkQueueFamilyProperties> fams(nf);
    vkGetPhysicalDeviceQueueFamilyProperties(physical_, &nf, fams.data());
    timestamp_valid_bits_ = fams[queue_family_].timestampValidBits;
  }
  // maxBufferSize (Vulkan 1.3) is chained only where the device reports 1.3.
  VkPhysicalDeviceMaintenance4Properties m4{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_MAINTENANCE_4_PROPERTIES};
  const bool has_m4 = props_.apiVersion >= VK_API_VERSION_1_3;
  VkPhysicalDeviceMaintenance3Properties m3{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_MAINTENANCE_3_PROPERTIES,
                                            has_m4 ? static_cast<void*>(&m4) : nullptr};
  VkPhysicalDeviceSubgroupProperties subgroup{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SUBGROUP_PROPERTIES, &m3};
  VkPhysicalDeviceFloatControlsProperties float_controls{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FLOAT_CONTROLS_PROPERTIES,
                                                         &subgroup};
  VkPhysicalDeviceDriverProperties driver{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_DRIVER_PROPERTIES, &float_controls};
  accel_props_.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_ACCELERATION_STRUCTURE_PROPERTIES_KHR;
  accel_props_.pNext = &driver;
  rt_props_.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_RAY_TRACING_PIPELINE_PROPERTIES_KHR;
  rt_props_.pNext = &accel_props_;
  void* chain = want_ray_pipeline ? static_cast<void*>(&rt_props_)
                : want_ray_query  ? static_cast<void*>(&accel_props_)
                                  : static_cast<void*>(&driver);
  VkPhysicalDeviceProperties2 p2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2, chain};
  vkGetPhysicalDeviceProperties2(physical_, &p2);
  accel_props_.pNext = nullptr;
  rt_props_.pNext = nullptr;
  driver_info_ = driver.driverInfo;
  subgroup_size_ = subgroup.subgroupSize > 0 ? subgroup.subgroupSize : 1;
  signed_zero_inf_nan_preserve_float32_ = float_controls.shaderSignedZeroInfNanPreserveFloat32 == VK_TRUE;
  max_allocation_ = m3.maxMemoryAllocationSize;
  if (has_m4 && m4.maxBufferSize < max_allocation_) {
    max_allocation_ = m4.maxBufferSize;
    max_allocation_name_ = "maxBufferSize";
  }
  VkPhysicalDeviceVulkan12Features have12{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES};
  VkPhysicalDeviceFeatures2 have{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2, &have12};
  vkGetPhysicalDeviceFeatures2(physical_, &have);
  buffer_device_address_ = have12.bufferDeviceAddress == VK_TRUE;

  float priority = 1.0f;
  VkDeviceQueueCreateInfo qci{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
  qci.queueFamilyIndex = queue_family_;
  qci.queueCount = 1;
  qci.pQueuePriorities = &priority;
  VkPhysicalDeviceRayQueryFeaturesKHR rq{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_RAY_QUERY_FEATURES_KHR};
  rq.rayQuery = VK_TRUE;
  VkPhysicalDeviceRayTracingPipelineFeaturesKHR rtf{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_RAY_TRACING_PIPELINE_FEATURES_KHR};
  rtf.rayTracingPipeline = VK_TRUE;
  VkPhysicalDeviceAccelerationStructureFeaturesKHR as{
      VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_ACCELERATION_STRUCTURE_FEATURES_KHR,
      want_ray_pipeline ? static_cast<void*>(&rtf) : static_cast<void*>(&rq)};
  as.accelerationStructure = VK_TRUE;
  VkPhysicalDeviceVulkan12Features v12{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES,
                                       want_structures ? &as : nullptr};
  v12.bufferDeviceAddress = buffer_device_address_ ? VK_TRUE : VK_FALSE;
  // Compile statistics of the pipelines (registers, spills: the GPU run's record of
  // what each kernel variant costs a thread), only when asked for: capturing them may
  // slow a driver's compiles.
  const bool stats_knob = knob_flag(Knob::VkPipelineStats, "vulkan");
  pipeline_statistics_ = stats_knob &&
                        device_has_extension(physical_, VK_KHR_PIPELINE_EXECUTABLE_PROPERTIES_EXTENSION_NAME);
  if (pipeline_statistics_) {
    VkPhysicalDevicePipelineExecutablePropertiesFeaturesKHR can{
        VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PIPELINE_EXECUTABLE_PROPERTIES_FEATURES_KHR};
    VkPhysicalDeviceFeatures2 f2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2, &can};
    vkGetPhysicalDeviceFeatures2(physical_, &f2);
    pipeline_statistics_ = can.pipelineExecutableInfo == VK_TRUE;
  }
  if (stats_knob && !pipeline_statistics_)
    std::fprintf(stderr, "masq: vulkan: MASQ_VK_PIPELINE_STATS: '%s' has no pipelineExecutableInfo "
                         "(VK_KHR_pipeline_executable_properties)\n", props_.deviceName);
  VkPhysicalDevicePipelineExecutablePropertiesFeaturesKHR exec_features{
      VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PIPELINE_EXECUTABLE_PROPERTIES_FEATURES_KHR, v12.pNext};
  exec_features.pipelineExecutableInfo = VK_TRUE;
  if (pipeline_statistics_) v12.pNext = &exec_features;
  std::vector<const char*> device_extensions;
  if (want_ray_query) device_extensions.assign(std::begin(kRayQueryExtensions), std::end(kRayQueryExtensions));
  else if (want_ray_pipeline) device_extensions.assign(std::begin(kRayPipelineExtensions), std::end(kRayPipelineExtensions));
  if (pipeline_statistics_) device_extensions.push_back(VK_KHR_PIPELINE_EXECUTABLE_PROPERTIES_EXTENSION_NAME);
  VkDeviceCreateInfo dci{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO, &v12};
  dci.queueCreateInfoCount = 1;
  dci.pQueueCreateInfos = &qci;
  dci.enabledExtensionCount = static_cast<std::uint32_t>(device_extensions.size());
  dci.ppEnabledExtensionNames = device_extensions.empty() ? nullptr : device_extensions.data();
  r = vkCreateDevice(physical_, &dci, nullptr, device_.put());
  if (r != VK_SUCCESS) {
    device_.release();
    unavailable(fmt::format("device '{}': vkCreateDevice: {}", props_.deviceName, result_name(r)));
  }
  vkGetDeviceQueue(device_.get(), queue_family_, 0, &queue_);
  VkCommandPoolCreateInfo pci{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
  pci.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
  pci.queueFamilyIndex = queue_family_;
  command_pool_ = {device_.get(), vkDestroyCommandPool};
  MASQ_VK_CHECK(vkCreateCommandPool(device_.get(), &pci, nullptr, command_pool_.put()));
  pipeline_cache_ = std::make_unique<PipelineCache>(physical_, device_.get());
  if (pipeline_statistics_) {
    executable_properties_ = reinterpret_cast<PFN_vkGetPipelineExecutablePropertiesKHR>(
        vkGetDeviceProcAddr(device_.get(), "vkGetPipelineExecutablePropertiesKHR"));
    executable_statistics_ = reinterpret_cast<PFN_vkGetPipelineExecutableStatisticsKHR>(
        vkGetDeviceProcAddr(device_.get(), "vkGetPipelineExecutableStatisticsKHR"));
    pipeline_statistics_ = executable_properties_ != nullptr && executable_statistics_ != nullptr;
  }

  ray_query_ = want_ray_query;
  ray_pipeline_ = want_ray_pipeline;
  if (want_structures) {
    auto load = [&](const char* name) {
      PFN_vkVoidFunction f = vkGetDeviceProcAddr(device_.get(), name);
      if (!f) unavailable(fmt::format("device '{}': no entry point {}", props_.deviceName, name));
      return f;
    };
    accel_.create = reinterpret_cast<PFN_vkCreateAccelerationStructureKHR>(load("vkCreateAccelerationStructureKHR"));
    accel_.destroy = reinterpret_cast<PFN_vkDestroyAccelerationStructureKHR>(load("vkDestroyAccelerationStructureKHR"));
    accel_.build_sizes = reinterpret_cast<PFN_vkGetAccelerationStructureBuildSizesKHR>(
        load("vkGetAccelerationStructureBuildSizesKHR"));
    accel_.cmd_build = reinterpret_cast<PFN_vkCmdBuildAccelerationStructuresKHR>(
        load("vkCmdBuildAccelerationStructuresKHR"));
    accel_.device_address = reinterpret_cast<PFN_vkGetAccelerationStructureDeviceAddressKHR>(
        load("vkGetAccelerationStructureDeviceAddressKHR"));
    accel_.cmd_write_properties = reinterpret_cast<PFN_vkCmdWriteAccelerationStructuresPropertiesKHR>(
        load("vkCmdWriteAccelerationStructuresPropertiesKHR"));
    accel_.cmd_copy =
        reinterpret_cast<PFN_vkCmdCopyAccelerationStructureKHR>(load("vkCmdCopyAccelerationStructureKHR"));
    if (want_ray_pipeline) {
      rt_.create = reinterpret_cast<PFN_vkCreateRayTracingPipelinesKHR>(load("vkCreateRayTracingPipelinesKHR"));
      rt_.group_handles = reinterpret_cast<PFN_vkGetRayTracingShaderGroupHandlesKHR>(
          load("vkGetRayTracingShaderGroupHandlesKHR"));
      rt_.cmd_trace = reinterpret_cast<PFN_vkCmdTraceRaysKHR>(load("vkCmdTraceRaysKHR"));
    }
  }
}

Context::~Context() {
  if (device_ && hung_) {
    // A dispatch that timed out may still run: waiting for the device would hang, and
    // destroying it under a running kernel is undefined. Leave it to process exit.
    std::fprintf(stderr, "masq: vulkan: device '%s' left open (a dispatch did not finish)\n", props_.deviceName);
    (void)shared_.release(); // its pipelines may be running
    command_pool_.release();
    device_.release();
    messenger_.release();
    instance_.release();
    return;
  }
  if (device_) vkDeviceWaitIdle(device_.get()); // the members then go, last made first
}

Staging& Context::staging() {
  std::lock_guard<std::mutex> lock(staging_mutex_);
  if (!staging_) staging_ = std::make_unique<Staging>(*this);
  return *staging_;
}

VkPipelineCache Context::pipeline_cache() const { return pipeline_cache_ ? pipeline_cache_->handle() : VK_NULL_HANDLE; }

std::uint64_t Context::validation_error_count() { return g_validation_errors.load(); }

void Context::check_validation() {
  if (!validation()) return;
  std::uint64_t now = g_validation_errors.load();
  if (now == validation_errors_seen_) return;
  std::uint64_t fresh = now - validation_errors_seen_;
  validation_errors_seen_ = now;
  std::lock_guard<std::mutex> lock(g_last_error_mutex);
  throw Error(fmt::format("vulkan: {} validation error(s) (MASQ_VK_VALIDATION), the last: {}", fresh, g_last_error));
}

std::string Context::device_name() const {
  return driver_info_.empty() ? std::string(props_.deviceName)
                              : fmt::format("{} [{}]", props_.deviceName, driver_info_);
}

std::uint64_t Context::max_storage_buffer_range() const {
  return lowered_limit("vulkan", props_.limits.maxStorageBufferRange, Knob::VkMaxBindingBytes);
}

std::uint64_t Context::max_allocation_bytes() const {
  return lowered_limit("vulkan", max_allocation_, Knob::VkMaxAllocationBytes);
}

std::uint64_t Context::max_allocation_count() const {
  return lowered_limit("vulkan", props_.limits.maxMemoryAllocationCount, Knob::VkMaxAllocations);
}

Context::Allocation Context::acquire_allocation() {
  const std::uint64_t limit = max_allocation_count();
  if (const std::uint64_t live = live_allocations_.fetch_add(1); live >= limit) {
    live_allocations_.fetch_sub(1);
    throw Error(fmt::format("vulkan: device '{}' holds {} memory allocations, and one more would exceed the limit {} "
                            "(maxMemoryAllocationCount {}, lowered by MASQ_VK_MAX_ALLOCATIONS)",
                            props_.deviceName, live, limit, props_.limits.maxMemoryAllocationCount));
  }
  return Allocation(this);
}

VkCommandBuffer Context::begin_commands() {
  if (lost_)
    throw Error(fmt::format("vulkan: device '{}' was lost earlier ({}); open the backend again", props_.deviceName,
                            hung_ ? "a dispatch did not finish within MASQ_VK_WAIT_SECONDS" : "VK_ERROR_DEVICE_LOST"));
  std::unique_lock<std::mutex> lock(submit_mutex_);
  VkCommandBufferAllocateInfo ai{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
  ai.commandPool = command_pool_.get();
  ai.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  ai.commandBufferCount = 1;
  VkCommandBuffer cmd = VK_NULL_HANDLE;
  MASQ_VK_CHECK(vkAllocateCommandBuffers(device_.get(), &ai, &cmd));
  VkCommandBufferBeginInfo bi{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
  bi.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  VkResult r = vkBeginCommandBuffer(cmd, &bi);
  if (r != VK_SUCCESS) {
    vkFreeCommandBuffers(device_.get(), command_pool_.get(), 1, &cmd);
    throw_vk_error("vkBeginCommandBuffer", r, __FILE__, __LINE__);
  }
  lock.release(); // held until submit_and_wait returns
  return cmd;
}

void Context::submit_and_wait(VkCommandBuffer cmd) {
  struct Free {
    Context* c;
    VkCommandBuffer b;
    VkFence f = VK_NULL_HANDLE;
    bool in_flight = false; // a wait that timed out: the GPU may still use both
    ~Free() {
      if (!in_flight) {
        if (f) vkDestroyFence(c->device(), f, nullptr);
        vkFreeCommandBuffers(c->device(), c->command_pool_.get(), 1, &b);
      }
      c->submit_mutex_.unlock(); // taken by begin_commands
    }
  } guard{this, cmd};
  const std::uint64_t seconds = wait_limit_seconds(); // a bad knob throws before anything is in flight
  MASQ_VK_CHECK(vkEndCommandBuffer(cmd));
  VkFenceCreateInfo fci{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
  MASQ_VK_CHECK(vkCreateFence(device_.get(), &fci, nullptr, &guard.f));
  VkSubmitInfo si{VK_STRUCTURE_TYPE_SUBMIT_INFO};
  si.commandBufferCount = 1;
  si.pCommandBuffers = &cmd;
  VkResult r = vkQueueSubmit(queue_, 1, &si, guard.f);
  if (r == VK_ERROR_DEVICE_LOST) throw_device_lost("vkQueueSubmit");
  if (r != VK_SUCCESS) throw_vk_error("vkQueueSubmit", r, __FILE__, __LINE__);
  // A bounded wait: a desktop GPU's watchdog resets a hung device (the wait then returns
  // VK_ERROR_DEVICE_LOST), but a compute GPU without a display has none. On an H200 a
  // trace kernel ran at 100% utilisation for minutes without returning (docs/results.md),
  // and masq would have waited forever. One dispatch holds at most
  // MASQ_MAX_RAYS_PER_DISPATCH rays, seconds of work even on a CPU driver, so the
  // default limit only ever catches a kernel that does not terminate.
  r = vkWaitForFences(device_.get(), 1, &guard.f, VK_TRUE, seconds * 1000000000ull);
  if (r == VK_SUCCESS && env_is_one(Knob::VkFaultDeviceLost)) r = VK_ERROR_DEVICE_LOST;
  if (r == VK_SUCCESS && env_is_one(Knob::VkFaultTimeout)) r = VK_TIMEOUT;
  if (r == VK_ERROR_DEVICE_LOST) throw_device_lost("vkWaitForFences");
  if (r == VK_TIMEOUT) {
    // The command buffer and fence may still be in use: leak them (and, at exit, the
    // device: ~Context does not wait for it) rather than free what the GPU is running.
    guard.in_flight = true;
    hung_ = true;
    lost_ = true;
    throw Error(fmt::format("vulkan: a dispatch on '{}' did not finish within {} s (MASQ_VK_WAIT_SECONDS): a kernel "
                            "that does not terminate on this device, or a dispatch too large for it (lower "
                            "MASQ_MAX_RAYS_PER_DISPATCH); this device is not used again by the process",
                            props_.deviceName, seconds));
  }
  if (r != VK_SUCCESS) throw_vk_error("vkWaitForFences", r, __FILE__, __LINE__);
  check_validation();
}

void Context::throw_device_lost(const char* call) {
  lost_ = true;
  throw Error(fmt::format("vulkan: device '{}' was lost ({}: VK_ERROR_DEVICE_LOST): the driver reset it, e.g. a "
                          "dispatch ran past its watchdog (lower MASQ_MAX_RAYS_PER_DISPATCH) or a kernel faulted; "
                          "backends opened from now on use a fresh device",
                          props_.deviceName, call));
}

} // namespace masq::vk
