#include "host/vulkan/vk_memory_placement.h"
#include "masq/error.h"
#include <fmt/format.h>
#include <algorithm>
#include <initializer_list>

namespace masq::vk {
namespace {

constexpr VkMemoryPropertyFlags kDL = VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT;
constexpr VkMemoryPropertyFlags kHV = VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT;
constexpr VkMemoryPropertyFlags kHC = VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
constexpr VkMemoryPropertyFlags kCached = VK_MEMORY_PROPERTY_HOST_CACHED_BIT;
// Never chosen: protected and lazily allocated memory cannot back a plain buffer the host
// or a compute shader uses, and AMD's device-coherent types may only be allocated with
// the deviceCoherentMemory feature enabled (masq does not enable it; they are also slow).
constexpr VkMemoryPropertyFlags kExcluded = VK_MEMORY_PROPERTY_PROTECTED_BIT | VK_MEMORY_PROPERTY_LAZILY_ALLOCATED_BIT |
                                            VK_MEMORY_PROPERTY_DEVICE_COHERENT_BIT_AMD |
                                            VK_MEMORY_PROPERTY_DEVICE_UNCACHED_BIT_AMD;

// How each role is served: the one table of roles.
enum class Kind {
  DeviceOnly,     // device memory, never mapped
  DeviceUploaded, // device memory the host fills: in place on a large host-visible heap, else staged
  Uniform,        // small and read by every thread: any device-local host-visible type, else staged
  StreamIn,       // read once by the device: host memory mapped in place (device-local if the heap is large)
  ReadBack,       // host-cached memory mapped in place
  Staging,        // host memory, mapped, cached so that readbacks through it are fast
};

struct RoleRow {
  BufferRole role;
  const char* name;
  Kind kind;
};

constexpr RoleRow kRoles[] = {
    {BufferRole::SceneData, "scene data", Kind::DeviceUploaded},
    {BufferRole::AccelStorage, "acceleration-structure storage", Kind::DeviceOnly},
    {BufferRole::AccelScratch, "acceleration-structure scratch", Kind::DeviceOnly},
    {BufferRole::AccelBuildInput, "acceleration-structure build input", Kind::DeviceUploaded},
    {BufferRole::UniformTable, "uniform table", Kind::Uniform},
    {BufferRole::RayInput, "rays", Kind::StreamIn},
    {BufferRole::Results, "results", Kind::ReadBack},
    {BufferRole::Staging, "staging", Kind::Staging},
};

const RoleRow& row(BufferRole role) {
  for (const RoleRow& r : kRoles)
    if (r.role == role) return r;
  throw Error("vulkan: unknown buffer role");
}

// One criterion of a ranking: the type has (want = true) or lacks (false) `bit`.
struct Criterion {
  VkMemoryPropertyFlags bit;
  bool want;
};

// The allowed type with all of `required`, ranked by `order` (earlier criteria weigh
// more); ties go to the lower index, which the spec orders by performance for equal
// flags. -1 when none qualifies.
int pick(const VkPhysicalDeviceMemoryProperties& mp, std::uint32_t type_bits, VkMemoryPropertyFlags required,
         std::initializer_list<Criterion> order) {
  int best = -1;
  std::uint32_t best_score = 0;
  for (std::uint32_t i = 0; i < mp.memoryTypeCount; ++i) {
    const VkMemoryPropertyFlags f = mp.memoryTypes[i].propertyFlags;
    if (!(type_bits & (1u << i)) || (f & kExcluded) || (f & required) != required) continue;
    std::uint32_t score = 0;
    for (const Criterion& c : order) score = (score << 1) | (((f & c.bit) != 0) == c.want ? 1u : 0u);
    if (best < 0 || score > best_score) {
      best = static_cast<int>(i);
      best_score = score;
    }
  }
  return best;
}

// Device memory the host does not map (avoids spending a small BAR window on it).
int device_type(const VkPhysicalDeviceMemoryProperties& mp, std::uint32_t bits) {
  return pick(mp, bits, kDL, {{kHV, false}});
}

// Host memory for sequential host writes: coherent, preferably not device-local (the BAR
// window is small) and write-combined rather than cached.
int host_write_type(const VkPhysicalDeviceMemoryProperties& mp, std::uint32_t bits) {
  return pick(mp, bits, kHV, {{kHC, true}, {kDL, false}, {kCached, false}});
}

// Host memory the host reads: cached first (uncached reads over PCIe are very slow),
// then coherent, then outside the BAR window.
int host_read_type(const VkPhysicalDeviceMemoryProperties& mp, std::uint32_t bits) {
  return pick(mp, bits, kHV, {{kCached, true}, {kHC, true}, {kDL, false}});
}

} // namespace

const char* role_name(BufferRole role) { return row(role).name; }

BufferRole default_role(VkBufferUsageFlags usage) {
  if (usage & VK_BUFFER_USAGE_ACCELERATION_STRUCTURE_STORAGE_BIT_KHR) return BufferRole::AccelStorage;
  if (usage & VK_BUFFER_USAGE_ACCELERATION_STRUCTURE_BUILD_INPUT_READ_ONLY_BIT_KHR)
    return BufferRole::AccelBuildInput;
  if (usage & VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT) return BufferRole::UniformTable;
  const VkBufferUsageFlags transfer = VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT;
  if ((usage & ~transfer) == 0) return BufferRole::Staging;
  return BufferRole::SceneData;
}

bool large_host_visible_device_heap(const VkPhysicalDeviceMemoryProperties& mp) {
  VkDeviceSize largest_device = 0, largest_visible = 0;
  for (std::uint32_t i = 0; i < mp.memoryTypeCount; ++i) {
    const VkMemoryType& t = mp.memoryTypes[i];
    if (!(t.propertyFlags & kDL) || (t.propertyFlags & kExcluded) || t.heapIndex >= mp.memoryHeapCount) continue;
    const VkDeviceSize heap = mp.memoryHeaps[t.heapIndex].size;
    largest_device = std::max(largest_device, heap);
    if (t.propertyFlags & kHV) largest_visible = std::max(largest_visible, heap);
  }
  return largest_visible > 0 && largest_visible >= largest_device / kInPlaceHeapDivisor;
}

MemoryPlacement place_buffer(BufferRole role, const VkPhysicalDeviceMemoryProperties& mp, std::uint32_t type_bits,
                             bool force_staging) {
  const Kind kind = row(role).kind;
  const bool in_place = !force_staging && large_host_visible_device_heap(mp);
  int type = -1;
  HostAccess host = HostAccess::Staged;
  switch (kind) {
  case Kind::DeviceOnly:
    type = device_type(mp, type_bits);
    host = HostAccess::None;
    break;
  case Kind::DeviceUploaded:
    if (in_place) {
      type = pick(mp, type_bits, kDL | kHV, {{kHC, true}});
      host = HostAccess::Mapped;
    }
    break;
  case Kind::Uniform:
    if (!force_staging) {
      type = pick(mp, type_bits, kDL | kHV, {{kHC, true}});
      host = HostAccess::Mapped;
    }
    break;
  case Kind::StreamIn:
    if (!force_staging) {
      type = in_place ? pick(mp, type_bits, kDL | kHV, {{kHC, true}}) : host_write_type(mp, type_bits);
      host = HostAccess::Mapped;
    }
    break;
  case Kind::ReadBack:
    if (!force_staging) {
      type = host_read_type(mp, type_bits);
      host = HostAccess::Mapped;
    }
    break;
  case Kind::Staging:
    type = host_read_type(mp, type_bits);
    host = HostAccess::Mapped;
    break;
  }
  if (type < 0 && host != HostAccess::None) { // the device path: device memory through staging
    type = device_type(mp, type_bits);
    host = HostAccess::Staged;
  }
  if (type < 0) type = pick(mp, type_bits, 0, {{kDL, true}}); // any type the buffer allows
  if (type < 0)
    throw Error(fmt::format("vulkan: no memory type can hold a {} buffer (memoryTypeBits 0x{:x})", role_name(role),
                            type_bits));
  const VkMemoryPropertyFlags f = mp.memoryTypes[type].propertyFlags;
  if (host == HostAccess::Mapped && !(f & kHV)) host = HostAccess::Staged;
  if (kind == Kind::Staging && host != HostAccess::Mapped)
    throw Error("vulkan: no host-visible memory type can hold the staging buffer");
  MemoryPlacement p;
  p.type_index = static_cast<std::uint32_t>(type);
  p.host = host;
  p.needs_flush_invalidate = host == HostAccess::Mapped && !(f & kHC);
  return p;
}

AtomRange atom_aligned_range(VkDeviceSize offset, VkDeviceSize bytes, VkDeviceSize atom,
                             VkDeviceSize allocation_size) {
  if (atom == 0) atom = 1;
  AtomRange r;
  r.offset = offset / atom * atom;
  VkDeviceSize end = (offset + bytes + atom - 1) / atom * atom;
  end = std::min(end, allocation_size);
  r.size = end > r.offset ? end - r.offset : 0;
  return r;
}

} // namespace masq::vk
