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

} // namespace masq
