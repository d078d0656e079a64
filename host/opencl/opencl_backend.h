// The opencl backend: kernels/trace.cl on the OpenCL device masq picks (the best-ranked,
// or the one MASQ_CL_DEVICE names; host/device_choice.h).
#pragma once
#include "host/backend.h"
#include "host/limit_knob.h"
#include <cstddef>
#include <memory>

namespace masq {
// Throws BackendUnavailable (one line) when no OpenCL platform or device exists.
// chunk_rays: rays per dispatch, which bounds the hit/stat buffers and keeps one kernel
// launch short for display GPUs' watchdogs (kMaxRaysPerDispatch, host/limit_knob.h;
// MASQ_MAX_RAYS_PER_DISPATCH lowers it at every trace). Tests pass small values to
// exercise the chunking.
std::unique_ptr<Backend> make_opencl_backend(std::size_t chunk_rays = kMaxRaysPerDispatch);
} // namespace masq
