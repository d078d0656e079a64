// What the compute and ray-query backends share: the scene arrays as storage buffers
// (bindings 0..6 and 10..12, each checked against maxStorageBufferRange), and tracing a batch of
// rays in chunks small enough that the ray, hit and stats buffers fit one binding and
// one dispatch.
#pragma once
#include "bvh/packed_scene.h"
#include "kernels/kernel_data.h"
#include "host/vulkan/vk_pipeline.h"
#include <array>
#include <span>

namespace masq::vk {

// Throws masq::Error "<backend>: <what> needs N bytes in one storage buffer; the device
// allows M (maxStorageBufferRange)" when bytes exceed the (possibly overridden) limit.
void check_storage_range(const Context& ctx, const char* backend, const char* what, std::uint64_t bytes);

struct SceneBuffers {
  // Indexed by binding: MASQ_BINDING_NODES .. MASQ_BINDING_CURVES (the per-ray
  // bindings 7..9 stay empty here; RayBatch owns them).
  std::array<Buffer, MASQ_BINDING_COUNT> arrays;
  std::size_t bytes = 0;        // real sizes (no dummies)
  void bind(KernelLayout& layout) const;
};
// Specialisation constants of the kernels (ids as in kernels/variants.h).
std::vector<std::uint32_t> spec_constants(const KernelFeatures& f, bool stats, bool any_hit, std::uint32_t local_size);

// with_bvh false: nodes and refs (masq's own BVH) get 16-byte dummies (ray query).
SceneBuffers upload_scene_arrays(Context& ctx, const char* backend, const PackedScene& scene, bool with_bvh = true);

class RayBatch {
 public:
  explicit RayBatch(Context& ctx) : ctx_(ctx) {}
  // Traces rays in chunks: binds rays/hits/stats (7/8/9) to `layout`, dispatches
  // `pipeline` with push constants {count, param, 0, 0} (kernel::TraceParams layout),
  // copies hits and stats back. Returns the device seconds summed over chunks.
  double run(const char* backend, KernelLayout& layout, VkPipeline pipeline, std::uint32_t local_size,
             std::int32_t param, std::span<const kernel::Ray> rays, std::span<kernel::Hit> hits,
             std::span<kernel::RayStats> stats);
  // Binds (dummy-sized if needed) ray buffers, e.g. before a warm-up dispatch.
  void bind_minimal(KernelLayout& layout);

 private:
  void ensure(std::size_t capacity, KernelLayout& layout);
  Context& ctx_;
  Buffer rays_, hits_, stats_;
  std::size_t capacity_ = 0;
};

} // namespace masq::vk
