// What the compute, bv and ray-query kernels share: the scene arrays (bound as storage
// buffers, or read through buffer device addresses when one exceeds
// maxStorageBufferRange) and tracing a batch of rays in chunks small enough that the
// ray, hit and stats buffers fit one binding and one dispatch, and that one dispatch
// stays short (max_rays_per_dispatch, host/limit_knob.h).
#pragma once
#include "host/backend.h"
#include "host/kernel_variant.h"
#include "host/scene_arrays.h"
#include "kernels/kernel_data.h"
#include "host/vulkan/vk_pipeline.h"
#include <functional>
#include <map>
#include <span>
#include <string>

namespace masq::vk {

// Throws masq::Error "<backend>: <what> needs N bytes in one storage buffer; the device
// allows M (maxStorageBufferRange)" when bytes exceed the (possibly lowered) limit.
void check_storage_range(const Context& ctx, const char* backend, const char* what, std::uint64_t bytes);

// Descriptor types of the kernels' layout: storage buffers at every binding below the
// address table (MASQ_BINDING_ADDRESSES, a uniform buffer); a kernel leaves unused the
// ones it does not read.
std::vector<VkDescriptorType> kernel_descriptor_types();

// The scene arrays of one kernel, by binding number (kernels/kernel_data.h). Bound mode:
// each array is a storage buffer at its binding. Addressed mode (chosen by finish() when
// an array exceeds maxStorageBufferRange and the device has bufferDeviceAddress): the
// kernel's *_addr_spv variant reads every array through the device address stored at
// slot `binding` of a uniform table; one array is then limited by
// maxMemoryAllocationSize (2 GiB on lavapipe) instead of one binding (128 MiB).
class SceneBuffers {
 public:
  // Throws masq::Error naming `what`, its size and the limit when one buffer cannot hold
  // it (max_allocation_bytes) or the allocation fails. `fill` writes the contents. An
  // array already at `binding` is replaced.
  void add(Context& ctx, const char* backend, std::uint32_t binding, const char* what, std::uint64_t size,
           const std::function<void(Buffer&)>& fill);
  template <class T>
  void add(Context& ctx, const char* backend, std::uint32_t binding, const char* what, const std::vector<T>& v) {
    std::uint64_t size = v.size() * sizeof(T);
    add(ctx, backend, binding, what, size, [&](Buffer& b) { b.upload(v.data(), size); });
  }
  // After the last add: picks the mode; throws the maxStorageBufferRange error when an
  // array exceeds one binding and the device cannot address it. prefer_addressed: use
  // addressed mode whenever the device can, not only for arrays over one binding.
  void finish(Context& ctx, const char* backend, bool prefer_addressed = false);
  bool addressed() const { return addressed_; }
  // Bound mode: every array at its binding and a dummy table; addressed mode: the table
  // and a dummy at every array binding (no descriptor then exceeds the range limit).
  void bind(KernelLayout& layout) const;
  std::size_t bytes = 0; // real sizes (no dummies)

 private:
  struct Array {
    Buffer buffer;
    std::string what;
    std::uint64_t bytes = 0;
  };
  std::map<std::uint32_t, Array> arrays_;
  Buffer table_, dummy_;
  bool addressed_ = false;
};

// The specialization constants of a kernel variant: value i goes to constant id i
// (kernels/variant_table.h), the work-group size to MASQ_SPEC_LOCAL_SIZE.
std::vector<std::uint32_t> spec_constants(const KernelVariant& v, std::uint32_t local_size);

// Adds every scene array `family`'s kernels read (kernels/scene_array_table.h) at its
// binding, empty ones included. A caller with arrays of its own (ray query's instance
// records) adds them afterwards at the same binding, replacing the scene's.
void add_scene_arrays(SceneBuffers& out, Context& ctx, const char* backend, const SceneArrayData& data,
                      KernelFamily family);

class RayBatch {
 public:
  explicit RayBatch(Context& ctx) : ctx_(ctx) {}
  // Where one run's time went, summed over chunks: device (timestamps around each
  // dispatch), upload (host time writing rays), readback (host time reading hits and
  // counters), wall (the whole run on the host clock).
  struct Times {
    double device = 0, upload = 0, readback = 0, wall = 0;
    void into(TraceTiming& t) const {
      t.trace_seconds = device;
      t.upload_seconds = upload;
      t.readback_seconds = readback;
      t.wall_seconds = wall;
    }
  };
  // Traces rays in chunks: binds rays/hits/stats (MASQ_BINDING_RAYS, _HITS, _STATS), dispatches
  // `pipeline` with push constants {count, param, 0, budget} (kernel::TraceParams layout),
  // copies hits and stats back. A chunk holds at most max_rays_per_dispatch rays
  // (host/limit_knob.h: the watchdog bound), besides what one binding and the group
  // count allow.
  Times run(const char* backend, KernelLayout& layout, VkPipeline pipeline, std::uint32_t local_size,
            std::int32_t param, std::span<const kernel::Ray> rays, std::span<kernel::Hit> hits,
            std::span<kernel::RayStats> stats, std::int32_t budget = 0);
  // The same chunking with the launch left to the caller: launch(n) traces the n rays
  // now in the ray buffer (bound at MASQ_BINDING_RAYS; hits and stats likewise) and
  // returns its device seconds. max_launch: the most rays one launch may hold.
  Times run_chunks(const char* backend, KernelLayout& layout, std::uint64_t max_launch,
                   std::span<const kernel::Ray> rays, std::span<kernel::Hit> hits, std::span<kernel::RayStats> stats,
                   const std::function<double(std::uint32_t n)>& launch);
  // The counters' buffer of the current chunk (valid inside launch; rtpipeline zeroes it).
  const Buffer& stats_buffer() const { return stats_; }
  // Binds (dummy-sized if needed) ray buffers, e.g. before a warm-up dispatch.
  void bind_minimal(KernelLayout& layout);

 private:
  void ensure(std::size_t capacity, KernelLayout& layout);
  Context& ctx_;
  Buffer rays_, hits_, stats_;
  std::size_t capacity_ = 0;
};

} // namespace masq::vk
