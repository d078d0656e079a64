// The opencl backend: kernels/trace.cl on the first OpenCL device (GPU preferred, else
// any, e.g. PoCL's pthread CPU device).
#pragma once
#include "host/backend.h"
#include "host/limit_knob.h"
#include <cstddef>
#include <memory>

namespace masq {
// Rays per dispatch: bounds the hit/stat staging buffers and keeps one kernel launch
// short enough for display-driven GPUs' watchdogs (kMaxRaysPerDispatch,
// host/limit_knob.h; MASQ_MAX_RAYS_PER_DISPATCH lowers it at every trace). Tests pass
// small values to exercise the chunking.
inline constexpr std::size_t kOpenClChunkRays = kMaxRaysPerDispatch;

// Throws BackendUnavailable (one line) when no OpenCL platform or device exists.
std::unique_ptr<Backend> make_opencl_backend(std::size_t chunk_rays = kOpenClChunkRays);
} // namespace masq
