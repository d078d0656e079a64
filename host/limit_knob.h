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

} // namespace masq
