// Device limits as the Vulkan backends use them: the driver's value, lowered (never
// raised) by an environment knob and by the test hook (vulkan_backends.h), so that
// tests and CI run the large-scene paths (addressed arrays, split TLAS/BLAS) and the
// over-the-limit errors on small scenes. Knobs (positive integers):
//   MASQ_VK_MAX_BINDING_BYTES     maxStorageBufferRange (one storage-buffer binding)
//   MASQ_VK_MAX_ALLOCATION_BYTES  maxMemoryAllocationSize / maxBufferSize (one array)
//   MASQ_RQ_MAX_INSTANCES         maxInstanceCount (instances per TLAS)
//   MASQ_RQ_MAX_PRIMITIVES        maxPrimitiveCount (primitives per BLAS)
#pragma once
#include <cstdint>

namespace masq::vk {

// min(device, $env, test_override), where an unset knob or a zero override is no limit.
// Throws masq::Error naming the knob when it is set but not a positive integer. Read at
// every call, so a knob set between scenes takes effect at the next set_scene.
std::uint64_t lowered_limit(std::uint64_t device, const char* env, std::uint64_t test_override);

} // namespace masq::vk
