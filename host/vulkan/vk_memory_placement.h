// Where a Vulkan buffer's memory lives and how the host reaches it, decided from the
// buffer's role and the device's memory types alone (no Vulkan calls: the decision is
// unit-tested with the memory properties of real devices given as data,
// tests/test_vk_memory_placement.cpp). docs/kernels.md, "Vulkan memory placement".
#pragma once
#include <vulkan/vulkan.h>
#include <cstdint>

namespace masq::vk {

// What a buffer holds, which fixes who reads and writes it how often.
enum class BufferRole {
  SceneData,       // scene arrays, BVH nodes, instances: host-written once, read per ray
  AccelStorage,    // acceleration-structure storage: written and read by the device only
  AccelScratch,    // acceleration-structure build scratch: device only
  AccelBuildInput, // geometry / instances an acceleration-structure build reads
  UniformTable,    // a small uniform block (the scene-array address table)
  RayInput,        // rays: host-written every chunk, read once per ray
  Results,         // hits and counters: device-written every chunk, read back by the host
  Staging,         // the transfer buffer between host and device memory
};

// Name of a role for messages ("scene data", "results"...).
const char* role_name(BufferRole role);

// How the host reaches a buffer's contents.
enum class HostAccess {
  None,   // never touched by the host (upload/download, if ever called, go through staging)
  Mapped, // mapped in place: host writes and reads go straight to the memory
  Staged, // device memory the host does not map: copies through the staging buffer
};

struct MemoryPlacement {
  std::uint32_t type_index = 0;
  HostAccess host = HostAccess::None;
  // Mapped but not HOST_COHERENT: host writes need vkFlushMappedMemoryRanges and device
  // writes vkInvalidateMappedMemoryRanges, on ranges aligned to nonCoherentAtomSize.
  bool needs_flush_invalidate = false;
};

// The role of a buffer made with Buffer(ctx, size, usage) and no role: acceleration-structure
// storage / build input by those usage bits, a uniform block, a transfer-only buffer as
// staging, any other storage buffer as scene data.
BufferRole default_role(VkBufferUsageFlags usage);

// A fraction of the largest device-local heap that a device-local, host-visible heap must
// reach for device data to be written in place rather than staged: 1/2. The 256 MiB BAR
// window of a discrete GPU without resizable BAR (NVIDIA, AMD) is a few percent of its
// VRAM; with resizable BAR, on integrated GPUs (UMA) and on lavapipe, the host-visible
// device-local heap is the whole device-local memory.
inline constexpr std::uint64_t kInPlaceHeapDivisor = 2;
// True when device data may be written in place (see kInPlaceHeapDivisor).
bool large_host_visible_device_heap(const VkPhysicalDeviceMemoryProperties& mp);

// The memory type and host access for a buffer of `role` whose memoryTypeBits are
// `type_bits`. force_staging (MASQ_VK_FORCE_STAGING=1) takes the discrete-GPU path on any
// device: only the staging buffer is mapped, everything else is device memory reached
// through copies. Throws masq::Error naming the role when no allowed type exists.
MemoryPlacement place_buffer(BufferRole role, const VkPhysicalDeviceMemoryProperties& mp, std::uint32_t type_bits,
                             bool force_staging);

// The range to flush or invalidate for bytes [offset, offset + bytes) of an allocation of
// allocation_size bytes: offset rounded down and the end rounded up to atom
// (nonCoherentAtomSize), the end clamped to the allocation (where the spec allows a
// size that is not a multiple of the atom).
struct AtomRange {
  VkDeviceSize offset = 0;
  VkDeviceSize size = 0;
};
AtomRange atom_aligned_range(VkDeviceSize offset, VkDeviceSize bytes, VkDeviceSize atom,
                             VkDeviceSize allocation_size);

} // namespace masq::vk
