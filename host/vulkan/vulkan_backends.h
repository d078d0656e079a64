// The Vulkan backends: "vulkan" (the shared traversal kernel as a compute shader),
// "rayquery" (the driver's own acceleration structures through VK_KHR_ray_query, calling
// the same intersector on every procedural candidate) and "rtpipeline" (the same
// structures through VK_KHR_ray_tracing_pipeline, the intersector as intersection shaders).
#pragma once
#include "host/backend.h"
#include <cstdint>
#include <memory>

namespace masq {

// Both throw BackendUnavailable with one line naming the cause.
std::unique_ptr<Backend> make_vulkan_backend();
std::unique_ptr<Backend> make_rayquery_backend();
std::unique_ptr<Backend> make_rtpipeline_backend();

// Test hook: make the backends behave as if the device's limits were at most these
// (0 keeps the device's own value), so the large-scene paths (arrays by address,
// split TLAS/BLAS), the too-large-scene errors and the chunked tracing can be exercised
// with small scenes. Read when a scene is set or traced. The environment knobs of
// host/limit_knob.h lower the same limits for whole runs (CLI, bench, ctest).
struct VulkanLimitOverrides {
  std::uint64_t max_storage_buffer_range = 0; // bytes in one storage-buffer binding
  std::uint64_t max_instance_count = 0;       // TLAS instances (rayquery, rtpipeline)
  std::uint64_t max_primitive_count = 0;      // primitives per BLAS (rayquery, rtpipeline)
  std::uint64_t max_allocation_bytes = 0;     // bytes in one array buffer
  std::uint64_t max_shader_group_stride = 0;  // bytes in one binding-table record (rtpipeline)
};
void set_limit_overrides_for_testing(const VulkanLimitOverrides& limits);
const VulkanLimitOverrides& limit_overrides_for_testing();

} // namespace masq
