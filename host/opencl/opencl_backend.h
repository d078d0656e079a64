// The opencl backend: kernels/trace.cl on the first OpenCL device (GPU preferred, else
// any, e.g. PoCL's pthread CPU device).
#pragma once
#include "host/backend.h"
#include <cstddef>
#include <memory>

namespace masq {
// Rays per dispatch: bounds the hit/stat staging buffers and keeps one kernel launch
// short enough for display-driven GPUs' watchdogs. Tests pass small values to
// exercise the chunking.
inline constexpr std::size_t kOpenClChunkRays = std::size_t{1} << 20;

// Throws BackendUnavailable (one line) when no OpenCL platform or device exists.
std::unique_ptr<Backend> make_opencl_backend(std::size_t chunk_rays = kOpenClChunkRays);
} // namespace masq
