// Device limits as the backends use them: the driver's value, lowered (never raised) by
// an environment knob and by a test hook, so that tests and CI run the large-scene
// paths (Vulkan arrays by address, split TLAS/BLAS) and the over-the-limit errors on
// small scenes. Knobs (positive integers, read at every use, so a knob set between
// scenes takes effect at the next set_scene):
//   MASQ_VK_MAX_BINDING_BYTES     vulkan, rayquery: maxStorageBufferRange (one binding)
//   MASQ_VK_MAX_ALLOCATION_BYTES  vulkan, rayquery: maxMemoryAllocationSize / maxBufferSize
//   MASQ_VK_STAGING_BYTES         vulkan, rayquery: the staging buffer's size (copies in pieces)
//   MASQ_RQ_MAX_INSTANCES         rayquery: maxInstanceCount (instances per TLAS)
//   MASQ_RQ_MAX_PRIMITIVES        rayquery: maxPrimitiveCount (primitives per BLAS)
//   MASQ_CL_MAX_ALLOC_BYTES       opencl: CL_DEVICE_MAX_MEM_ALLOC_SIZE
//   MASQ_VK_MAX_ALLOCATIONS       vulkan, rayquery: maxMemoryAllocationCount (live
//                                 allocations per device, counted by vk::Buffer)
//   MASQ_VK_WAIT_SECONDS          vulkan, rayquery: seconds one submission may take
//                                 (host/vulkan/vk_context.h, kDefaultWaitSeconds)
//   MASQ_MAX_RAYS_PER_DISPATCH    vulkan, rayquery, opencl (and their bv tracers): rays in
//                                 one dispatch, kMaxRaysPerDispatch by default (below)
#pragma once
#include "masq/error.h"
#include <algorithm>
#include <cerrno>
#include <cstdint>
#include <cstdlib>
#include <string>

namespace masq {

// min(device, $env, test_override), where an unset knob or a zero override is no limit.
// Throws masq::Error "<backend>: <env>='<value>' is not a positive integer".
inline std::uint64_t lowered_limit(const char* backend, std::uint64_t device, const char* env,
                                   std::uint64_t test_override = 0) {
  std::uint64_t limit = device;
  if (test_override != 0) limit = std::min(limit, test_override);
  const char* v = std::getenv(env);
  if (v == nullptr || *v == '\0') return limit;
  char* end = nullptr;
  errno = 0;
  unsigned long long n = std::strtoull(v, &end, 10);
  if (*end != '\0' || errno != 0 || n == 0 || *v == '-' || *v == '+' || *v == ' ')
    throw Error(std::string(backend) + ": " + env + "='" + v + "' is not a positive integer");
  return std::min<std::uint64_t>(limit, n);
}

// The value of a knob that names one of two choices: true for `on`, false for `off`,
// `fallback` when unset or empty. Throws masq::Error "<owner>: <env>='<value>' is not
// '<on>' or '<off>'" (owner: the backend, or "" for a knob of every backend).
inline bool choice_knob(const char* owner, const char* env, const char* on, const char* off, bool fallback) {
  const char* v = std::getenv(env);
  if (v == nullptr || *v == '\0') return fallback;
  if (std::string(v) == on) return true;
  if (std::string(v) == off) return false;
  throw Error(std::string(owner) + (*owner ? ": " : "") + env + "='" + v + "' is not '" + on + "' or '" + off + "'");
}

// Rays in one dispatch unless MASQ_MAX_RAYS_PER_DISPATCH lowers it. A display GPU's
// driver resets a kernel that runs past about 2 s (Windows TDR, Linux/macOS watchdogs).
// masq's slowest traces, the counter variants on dense hair, run near 1 Mrays/s on the
// two llvmpipe cores here and at 10-100x that on a GPU; 2^20 rays is then well under
// a tenth of a second per dispatch on a GPU (about 1 s on this machine's CPU drivers,
// which have no watchdog), while one dispatch still holds far more rays than any GPU
// runs at once (an H100: 132 SMs x 2048 threads = 270K), so chunking costs only a
// submit per 2^20 rays.
inline constexpr std::uint64_t kMaxRaysPerDispatch = std::uint64_t{1} << 20;

inline std::uint64_t max_rays_per_dispatch(const char* backend) {
  return lowered_limit(backend, kMaxRaysPerDispatch, "MASQ_MAX_RAYS_PER_DISPATCH");
}

} // namespace masq
