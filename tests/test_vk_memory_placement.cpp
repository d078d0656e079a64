// Vulkan memory placement (host/vulkan/vk_memory_placement.h): the decision checked on
// the memory properties of real devices given as data, then buffers on this machine's
// device placed both ways (in place, and through the staging buffer with
// MASQ_VK_FORCE_STAGING) with data round trips that cross the staging buffer's pieces.
// SyncBarriers records masq's barriers around a staged upload, a dispatch and a staged
// readback in one command buffer under synchronization validation: no hazard with them,
// a read-after-write hazard without the upload's. Vulkan missing fails the device tests
// unless MASQ_ALLOW_MISSING_BACKENDS=1.
#include "host/vulkan/vk_barriers.h"
#include "host/vulkan/vk_buffer.h"
#include "host/vulkan/vk_memory_placement.h"
#include "host/vulkan/vk_pipeline.h"
#include "host/vulkan/vk_staging.h"
#include "spirv/scale_words_comp_spv.h"
#include "tests/test_env.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <cstdlib>
#include <initializer_list>
#include <numeric>
#include <set>
#include <string>
#include <vector>

namespace {

using namespace masq;
using namespace masq::vk;

constexpr VkMemoryPropertyFlags DL = VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT;
constexpr VkMemoryPropertyFlags HV = VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT;
constexpr VkMemoryPropertyFlags HC = VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
constexpr VkMemoryPropertyFlags CACHED = VK_MEMORY_PROPERTY_HOST_CACHED_BIT;
constexpr VkMemoryPropertyFlags AMD_DC =
    VK_MEMORY_PROPERTY_DEVICE_COHERENT_BIT_AMD | VK_MEMORY_PROPERTY_DEVICE_UNCACHED_BIT_AMD;
constexpr std::uint32_t kAll = ~0u;

struct Type {
  VkMemoryPropertyFlags flags;
  std::uint32_t heap;
};

VkPhysicalDeviceMemoryProperties device(std::initializer_list<VkDeviceSize> heaps, std::initializer_list<Type> types) {
  VkPhysicalDeviceMemoryProperties mp{};
  for (VkDeviceSize size : heaps) {
    mp.memoryHeaps[mp.memoryHeapCount].size = size;
    mp.memoryHeapCount++;
  }
  for (const Type& t : types) {
    mp.memoryTypes[mp.memoryTypeCount] = {t.flags, t.heap};
    if (t.flags & DL) mp.memoryHeaps[t.heap].flags = VK_MEMORY_HEAP_DEVICE_LOCAL_BIT;
    mp.memoryTypeCount++;
  }
  return mp;
}

// NVIDIA discrete: the four memory types an NVIDIA driver lists in
// KhronosGroup/Vulkan-ValidationLayers#5908 (device-local VRAM; host memory coherent;
// the BAR window device-local + host-visible; host memory cached), with the heap sizes
// of an RTX 3070 from cg-tuwien/Auto-Vk#66 (8,433,696,768 B VRAM, 17,141,145,600 B
// host, 224,395,264 B BAR: NVIDIA's 256 MiB window less what the driver keeps).
VkPhysicalDeviceMemoryProperties nvidia_discrete() {
  return device({8433696768ull, 17141145600ull, 224395264ull},
                {{DL, 0}, {HV | HC, 1}, {DL | HV | HC, 2}, {HV | HC | CACHED, 1}});
}

// AMD discrete without resizable BAR (RADV, Radeon RX with 7.75 GiB VRAM):
// nowrep/obs-vkcapture#6 lists the heaps (8,321,499,136 B VRAM, 8,573,157,376 B host,
// 268,435,456 B visible VRAM) and types 0-1; types 2-3 are the visible-VRAM and cached
// host types and 4-7 the same four with AMD's device-coherent/uncached flags (8 types in
// all, as reported there; GpuZelenograd/memtest_vulkan#1 shows those flags on RADV).
VkPhysicalDeviceMemoryProperties amd_small_bar() {
  return device({8321499136ull, 8573157376ull, 268435456ull},
                {{DL, 0},
                 {HV | HC, 1},
                 {DL | HV | HC, 2},
                 {HV | HC | CACHED, 1},
                 {DL | AMD_DC, 0},
                 {HV | HC | AMD_DC, 1},
                 {DL | HV | HC | AMD_DC, 2},
                 {HV | HC | CACHED | AMD_DC, 1}});
}

// AMD discrete with resizable BAR: GpuZelenograd/memtest_vulkan#1 (RX 5700, RADV) shows
// the visible-VRAM heap merged into one 8.0 GB device-local heap beside 15.6 GB of host
// memory; the types are RADV's, now with the host-visible VRAM type on the whole VRAM.
VkPhysicalDeviceMemoryProperties amd_resizable_bar() {
  return device({16750372454ull, 8589934592ull},
                {{DL, 1}, {HV | HC, 0}, {DL | HV | HC, 1}, {HV | HC | CACHED, 0}});
}

// Intel integrated (UMA) on Mesa's ANV with a last-level cache shared with the CPU: one
// heap, one type both cached and coherent (anv_device.c as quoted in doitsujin/dxvk#947);
// 8 GB unified as the UHD 620 of GPUOpen-Effects/FidelityFX-FSR2#87.
VkPhysicalDeviceMemoryProperties intel_integrated() {
  return device({8589934592ull}, {{DL | HV | HC | CACHED, 0}});
}

// Intel Atom (ANV without a shared LLC, doitsujin/dxvk#947): coherent-uncached and
// cached-non-coherent, so reads back need vkInvalidateMappedMemoryRanges.
VkPhysicalDeviceMemoryProperties intel_atom() {
  return device({4294967296ull}, {{DL | HV | HC, 0}, {DL | HV | CACHED, 0}});
}

// lavapipe (Mesa 25.0.7, this machine's vulkaninfo): one heap, one type with every flag.
VkPhysicalDeviceMemoryProperties lavapipe() {
  return device({25276510208ull}, {{DL | HV | HC | CACHED, 0}});
}

void expect(const VkPhysicalDeviceMemoryProperties& mp, BufferRole role, bool force, std::uint32_t type,
            HostAccess host, bool flush = false) {
  SCOPED_TRACE(std::string(role_name(role)) + (force ? " (forced staging)" : ""));
  MemoryPlacement p = place_buffer(role, mp, kAll, force);
  EXPECT_EQ(p.type_index, type);
  EXPECT_EQ(p.host, host);
  EXPECT_EQ(p.needs_flush_invalidate, flush);
}

TEST(MemoryPlacement, NvidiaDiscreteStagesDeviceDataAndReadsBackFromCachedHostMemory) {
  const auto mp = nvidia_discrete();
  EXPECT_FALSE(large_host_visible_device_heap(mp)); // 214 MiB of 7.85 GiB
  expect(mp, BufferRole::SceneData, false, 0, HostAccess::Staged);
  expect(mp, BufferRole::AccelBuildInput, false, 0, HostAccess::Staged);
  expect(mp, BufferRole::AccelStorage, false, 0, HostAccess::None);
  expect(mp, BufferRole::AccelScratch, false, 0, HostAccess::None);
  expect(mp, BufferRole::UniformTable, false, 2, HostAccess::Mapped); // the BAR window
  expect(mp, BufferRole::RayInput, false, 1, HostAccess::Mapped);     // write-combined host memory
  expect(mp, BufferRole::Results, false, 3, HostAccess::Mapped);      // cached host memory
  expect(mp, BufferRole::Staging, false, 3, HostAccess::Mapped);
  // Forced staging changes nothing for device data; rays, results and the table move to VRAM.
  expect(mp, BufferRole::SceneData, true, 0, HostAccess::Staged);
  expect(mp, BufferRole::UniformTable, true, 0, HostAccess::Staged);
  expect(mp, BufferRole::RayInput, true, 0, HostAccess::Staged);
  expect(mp, BufferRole::Results, true, 0, HostAccess::Staged);
  expect(mp, BufferRole::Staging, true, 3, HostAccess::Mapped);
}

TEST(MemoryPlacement, AmdWithoutResizableBarAvoidsDeviceCoherentTypes) {
  const auto mp = amd_small_bar();
  EXPECT_FALSE(large_host_visible_device_heap(mp));
  expect(mp, BufferRole::SceneData, false, 0, HostAccess::Staged);
  expect(mp, BufferRole::UniformTable, false, 2, HostAccess::Mapped);
  expect(mp, BufferRole::RayInput, false, 1, HostAccess::Mapped);
  expect(mp, BufferRole::Results, false, 3, HostAccess::Mapped);
  expect(mp, BufferRole::Staging, false, 3, HostAccess::Mapped);
  // Only device-coherent types allowed: no type qualifies (they need deviceCoherentMemory).
  const std::uint32_t amd_only = 0xf0u;
  try {
    place_buffer(BufferRole::SceneData, mp, amd_only, false);
    ADD_FAILURE() << "a device-coherent type was chosen";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("scene data"), std::string::npos) << e.what();
  }
}

TEST(MemoryPlacement, AmdWithResizableBarWritesDeviceDataInPlace) {
  const auto mp = amd_resizable_bar();
  EXPECT_TRUE(large_host_visible_device_heap(mp));
  expect(mp, BufferRole::SceneData, false, 2, HostAccess::Mapped);
  expect(mp, BufferRole::AccelBuildInput, false, 2, HostAccess::Mapped);
  expect(mp, BufferRole::AccelStorage, false, 0, HostAccess::None); // the host never maps it
  expect(mp, BufferRole::RayInput, false, 2, HostAccess::Mapped);
  expect(mp, BufferRole::Results, false, 3, HostAccess::Mapped); // never read VRAM over the BAR
  expect(mp, BufferRole::SceneData, true, 0, HostAccess::Staged);
  expect(mp, BufferRole::Results, true, 0, HostAccess::Staged);
}

TEST(MemoryPlacement, IntegratedAndLavapipeMapEverythingUnlessForced) {
  for (const auto& mp : {intel_integrated(), lavapipe()}) {
    EXPECT_TRUE(large_host_visible_device_heap(mp));
    for (BufferRole r : {BufferRole::SceneData, BufferRole::AccelBuildInput, BufferRole::UniformTable,
                         BufferRole::RayInput, BufferRole::Results, BufferRole::Staging})
      expect(mp, r, false, 0, HostAccess::Mapped);
    expect(mp, BufferRole::AccelStorage, false, 0, HostAccess::None);
    // Forced: the discrete path, only staging mapped (MASQ_VK_FORCE_STAGING=1 on lavapipe).
    for (BufferRole r : {BufferRole::SceneData, BufferRole::AccelBuildInput, BufferRole::UniformTable,
                         BufferRole::RayInput, BufferRole::Results})
      expect(mp, r, true, 0, HostAccess::Staged);
    expect(mp, BufferRole::Staging, true, 0, HostAccess::Mapped);
  }
}

TEST(MemoryPlacement, NonCoherentCachedMemoryNeedsInvalidation) {
  const auto mp = intel_atom();
  expect(mp, BufferRole::Results, false, 1, HostAccess::Mapped, true); // cached beats coherent for reads
  expect(mp, BufferRole::Staging, false, 1, HostAccess::Mapped, true);
  expect(mp, BufferRole::SceneData, false, 0, HostAccess::Mapped); // writes: coherent
  expect(mp, BufferRole::RayInput, false, 0, HostAccess::Mapped);
}

TEST(MemoryPlacement, MemoryTypeBitsAreHonoured) {
  const auto mp = nvidia_discrete();
  // VRAM type not allowed: the BAR type serves device data, still reached through staging.
  MemoryPlacement p = place_buffer(BufferRole::SceneData, mp, 0b1110u, false);
  EXPECT_EQ(p.type_index, 2u);
  EXPECT_EQ(p.host, HostAccess::Staged);
  // Only host memory allowed: results still mapped, from the coherent type.
  p = place_buffer(BufferRole::Results, mp, 0b0010u, false);
  EXPECT_EQ(p.type_index, 1u);
  EXPECT_EQ(p.host, HostAccess::Mapped);
  EXPECT_THROW(place_buffer(BufferRole::SceneData, mp, 0u, false), Error);
}

TEST(MemoryPlacement, InPlaceThresholdIsHalfTheLargestDeviceHeap) {
  auto with_window = [](VkDeviceSize window) {
    return device({8ull << 30, 16ull << 30, window}, {{DL, 0}, {HV | HC, 1}, {DL | HV | HC, 2}});
  };
  EXPECT_TRUE(large_host_visible_device_heap(with_window(4ull << 30)));
  EXPECT_FALSE(large_host_visible_device_heap(with_window((4ull << 30) - 1)));
  EXPECT_FALSE(large_host_visible_device_heap(with_window(256ull << 20)));
}

TEST(MemoryPlacement, DefaultRolesFromUsage) {
  EXPECT_EQ(default_role(VK_BUFFER_USAGE_STORAGE_BUFFER_BIT), BufferRole::SceneData);
  EXPECT_EQ(default_role(VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT),
            BufferRole::SceneData);
  EXPECT_EQ(default_role(VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT), BufferRole::UniformTable);
  EXPECT_EQ(default_role(VK_BUFFER_USAGE_ACCELERATION_STRUCTURE_STORAGE_BIT_KHR |
                         VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT),
            BufferRole::AccelStorage);
  EXPECT_EQ(default_role(VK_BUFFER_USAGE_ACCELERATION_STRUCTURE_BUILD_INPUT_READ_ONLY_BIT_KHR |
                         VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT),
            BufferRole::AccelBuildInput);
  EXPECT_EQ(default_role(0), BufferRole::Staging);
  std::set<std::string> names;
  for (BufferRole r : {BufferRole::SceneData, BufferRole::AccelStorage, BufferRole::AccelScratch,
                       BufferRole::AccelBuildInput, BufferRole::UniformTable, BufferRole::RayInput,
                       BufferRole::Results, BufferRole::Staging})
    EXPECT_TRUE(names.insert(role_name(r)).second) << role_name(r);
}

TEST(MemoryPlacement, AtomAlignedRanges) {
  AtomRange r = atom_aligned_range(100, 50, 64, 4096);
  EXPECT_EQ(r.offset, 64u);
  EXPECT_EQ(r.size, 128u); // [64, 192)
  r = atom_aligned_range(4000, 96, 256, 4096); // the end clamps to the allocation
  EXPECT_EQ(r.offset, 3840u);
  EXPECT_EQ(r.size, 256u);
  r = atom_aligned_range(4000, 90, 256, 4090);
  EXPECT_EQ(r.offset + r.size, 4090u);
  r = atom_aligned_range(7, 9, 0, 100); // atom 0 treated as 1
  EXPECT_EQ(r.offset, 7u);
  EXPECT_EQ(r.size, 9u);
}

// On this machine's device: a buffer placed in place and one reached through staging in
// pieces smaller than the data (MASQ_VK_STAGING_BYTES) hold the same bytes after a round
// trip at an odd offset.
TEST(MemoryPlacementDevice, RoundTripsInPlaceAndThroughStagingPieces) {
  std::shared_ptr<Context> ctx;
  try {
    ctx = Context::get("vulkan");
  } catch (const BackendUnavailable& e) {
    if (masq::test::missing_backends_allowed()) GTEST_SKIP() << e.what();
    FAIL() << e.what();
  }
  std::vector<std::uint8_t> data(100003);
  std::iota(data.begin(), data.end(), std::uint8_t(7));
  const char* forced_before = std::getenv("MASQ_VK_FORCE_STAGING");
  const std::string keep = forced_before ? forced_before : "";
  for (bool force : {false, true}) {
    SCOPED_TRACE(force ? "forced staging" : "default placement");
    setenv("MASQ_VK_FORCE_STAGING", force ? "1" : "0", 1);
    setenv("MASQ_VK_STAGING_BYTES", "4096", 1);
    Buffer b(*ctx, data.size() + 64, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
    if (force) {
      EXPECT_FALSE(b.mapped());
    }
    Buffer results(*ctx, data.size() + 64, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, BufferRole::Results);
    EXPECT_EQ(results.mapped(), !force);
    for (Buffer* buf : {&b, &results}) {
      buf->upload(data.data(), data.size(), 13);
      std::vector<std::uint8_t> back(data.size());
      buf->download(back.data(), back.size(), 13);
      EXPECT_EQ(back, data);
    }
    // Staging first used here, under the 4096-byte cap: 100,003 bytes went in 25 pieces.
    if (force) {
      EXPECT_EQ(ctx->staging().capacity(), 4096u);
    }
  }
  unsetenv("MASQ_VK_STAGING_BYTES");
  if (forced_before) setenv("MASQ_VK_FORCE_STAGING", keep.c_str(), 1);
  else unsetenv("MASQ_VK_FORCE_STAGING");
}

// Records: upload copy (staging -> in), the kernel (in -> out), readback copy (out ->
// staging), with masq's barriers, the upload's left out when `skip_upload_barrier`.
// Returns the submission's error ("" when none) and fills `got`.
std::string staged_round_trip(Context& ctx, bool skip_upload_barrier, std::vector<std::uint32_t>& got) {
  const std::uint32_t n = 1000;
  const VkDeviceSize bytes = n * sizeof(std::uint32_t);
  Buffer up(ctx, bytes, 0, BufferRole::Staging), down(ctx, bytes, 0, BufferRole::Staging);
  Buffer in(ctx, bytes, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT), out(ctx, bytes, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
  std::vector<std::uint32_t> words(n);
  std::iota(words.begin(), words.end(), 5u);
  up.upload(words.data(), bytes);
  KernelLayout layout(ctx, {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER}, sizeof(n));
  layout.bind_buffer(0, in);
  layout.bind_buffer(1, out);
  DeviceOwned<VkPipeline> pipeline = layout.create_pipeline(scale_words_comp_spv, {});
  VkCommandBuffer cmd = ctx.begin_commands();
  const VkBufferCopy region{0, 0, bytes};
  barrier_before_copy(ctx, cmd);
  vkCmdCopyBuffer(cmd, up.handle(), in.handle(), 1, &region);
  if (!skip_upload_barrier) barrier_after_upload(ctx, cmd);
  vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline.get());
  VkDescriptorSet set = layout.set();
  vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, layout.pipeline_layout(), 0, 1, &set, 0, nullptr);
  vkCmdPushConstants(cmd, layout.pipeline_layout(), VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(n), &n);
  vkCmdDispatch(cmd, (n + 63) / 64, 1, 1);
  barrier_after_dispatch(cmd);
  barrier_before_copy(ctx, cmd);
  vkCmdCopyBuffer(cmd, out.handle(), down.handle(), 1, &region);
  barrier_after_readback(ctx, cmd);
  std::string error;
  try {
    ctx.submit_and_wait(cmd);
  } catch (const Error& e) {
    error = e.what();
  }
  got.assign(n, 0);
  down.download(got.data(), bytes);
  return error;
}

TEST(SyncBarriers, StagedUploadDispatchReadbackInOneCommandBuffer) {
  // This test's own context gets synchronization validation (each ctest case is its own
  // process; run with the others, no context is alive when it starts).
  setenv("MASQ_VK_VALIDATION", "sync", 1);
  std::shared_ptr<Context> ctx;
  try {
    ctx = Context::get("vulkan");
  } catch (const BackendUnavailable& e) {
    if (masq::test::missing_backends_allowed()) GTEST_SKIP() << e.what();
    FAIL() << e.what();
  }
  ASSERT_TRUE(ctx->validation());
  std::vector<std::uint32_t> got;
  EXPECT_EQ(staged_round_trip(*ctx, false, got), "");
  for (std::uint32_t i = 0; i < got.size(); ++i) ASSERT_EQ(got[i], (5u + i) * 3u + 1u) << i;
  // Without the upload's barrier the kernel reads what the copy may not have written.
  const std::string hazard = staged_round_trip(*ctx, true, got);
  EXPECT_NE(hazard.find("SYNC-HAZARD-READ-AFTER-WRITE"), std::string::npos) << hazard;
}

} // namespace

