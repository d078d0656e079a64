#include "host/vulkan/trace_dispatch.h"
#include "kernels/kernel_data.h"
#include <fmt/format.h>
#include <algorithm>

namespace masq::vk {
namespace {

void upload_bytes(Context& ctx, const char* backend, const char* what, const void* data, std::uint64_t bytes,
                  Buffer& out, std::size_t& total) {
  check_storage_range(ctx, backend, what, bytes);
  out = Buffer(ctx, bytes, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
  out.upload(data, bytes);
  total += bytes;
}

template <class T>
void upload_array(Context& ctx, const char* backend, const char* what, const std::vector<T>& v, Buffer& out,
                  std::size_t& total) {
  upload_bytes(ctx, backend, what, v.data(), v.size() * sizeof(T), out, total);
}

} // namespace

void check_storage_range(const Context& ctx, const char* backend, const char* what, std::uint64_t bytes) {
  std::uint64_t limit = ctx.max_storage_buffer_range();
  if (bytes > limit)
    throw Error(fmt::format("{}: {} needs {} bytes in one storage buffer; the device allows {} "
                            "(maxStorageBufferRange)",
                            backend, what, bytes, limit));
}

void SceneBuffers::bind(KernelLayout& layout) const {
  for (std::uint32_t i = 0; i < arrays.size(); ++i)
    if (arrays[i].valid()) layout.bind_buffer(i, arrays[i]);
}

SceneBuffers upload_scene_arrays(Context& ctx, const char* backend, const PackedScene& s, bool with_bvh) {
  SceneBuffers b;
  if (with_bvh) {
    // Whatever the node format: the kernels read w8 and q8 through an alias of this binding.
    upload_bytes(ctx, backend, "scene nodes", s.node_data(), s.node_bytes(), b.arrays[MASQ_BINDING_NODES], b.bytes);
    upload_array(ctx, backend, "scene refs", s.refs, b.arrays[MASQ_BINDING_REFS], b.bytes);
  } else {
    b.arrays[MASQ_BINDING_NODES] = Buffer(ctx, 16, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
    b.arrays[MASQ_BINDING_REFS] = Buffer(ctx, 16, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
  }
  upload_array(ctx, backend, "scene instances", s.instances, b.arrays[MASQ_BINDING_INSTANCES], b.bytes);
  upload_array(ctx, backend, "scene frames", s.frames, b.arrays[MASQ_BINDING_FRAMES], b.bytes);
  upload_array(ctx, backend, "scene geoms", s.geoms, b.arrays[MASQ_BINDING_GEOMS], b.bytes);
  upload_array(ctx, backend, "scene triangles", s.triangles, b.arrays[MASQ_BINDING_TRIANGLES], b.bytes);
  upload_array(ctx, backend, "scene capsules", s.capsules, b.arrays[MASQ_BINDING_CAPSULES], b.bytes);
  upload_array(ctx, backend, "scene round cones", s.cones, b.arrays[MASQ_BINDING_CONES], b.bytes);
  upload_array(ctx, backend, "scene spheres", s.spheres, b.arrays[MASQ_BINDING_SPHERES], b.bytes);
  upload_array(ctx, backend, "scene curves", s.curves, b.arrays[MASQ_BINDING_CURVES], b.bytes);
  return b;
}

std::vector<std::uint32_t> spec_constants(const KernelFeatures& f, bool stats, bool any_hit, std::uint32_t local_size) {
  return {stats,     f.triangles, f.capsules, local_size, f.cones, f.spheres, f.curves, f.mode == Mode::Robust,
          static_cast<std::uint32_t>(f.curve_iters), any_hit, f.single_blas,
          static_cast<std::uint32_t>(node_format_id(f.nodes))};
}

void RayBatch::ensure(std::size_t capacity, KernelLayout& layout) {
  if (capacity > capacity_ || !rays_.valid()) {
    rays_ = Buffer(ctx_, capacity * sizeof(kernel::Ray), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
    hits_ = Buffer(ctx_, capacity * sizeof(kernel::Hit), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
    stats_ = Buffer(ctx_, capacity * sizeof(kernel::RayStats), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
    capacity_ = capacity;
  }
  layout.bind_buffer(MASQ_BINDING_RAYS, rays_);
  layout.bind_buffer(MASQ_BINDING_HITS, hits_);
  layout.bind_buffer(MASQ_BINDING_STATS, stats_);
}

void RayBatch::bind_minimal(KernelLayout& layout) { ensure(std::max<std::size_t>(capacity_, 1), layout); }

double RayBatch::run(const char* backend, KernelLayout& layout, VkPipeline pipeline, std::uint32_t local_size,
                     std::int32_t param, std::span<const kernel::Ray> rays, std::span<kernel::Hit> hits,
                     std::span<kernel::RayStats> stats) {
  if (hits.size() != rays.size())
    throw Error(fmt::format("{}: trace: {} rays but {} hits", backend, rays.size(), hits.size()));
  if (!stats.empty() && stats.size() != rays.size())
    throw Error(fmt::format("{}: trace: {} rays but {} stats", backend, rays.size(), stats.size()));
  if (rays.empty()) return 0.0;
  // Chunk: every per-ray buffer within one binding, the group count within the limit,
  // and the count within a push-constant int.
  std::uint64_t limit = ctx_.max_storage_buffer_range();
  std::uint64_t chunk = limit / sizeof(kernel::Hit);
  chunk = std::min<std::uint64_t>(chunk, limit / sizeof(kernel::Ray));
  chunk = std::min<std::uint64_t>(chunk, std::uint64_t(ctx_.props.limits.maxComputeWorkGroupCount[0]) * local_size);
  chunk = std::min<std::uint64_t>(chunk, 1u << 30);
  chunk = std::min<std::uint64_t>(chunk, rays.size());
  if (chunk == 0) throw Error(fmt::format("{}: maxStorageBufferRange {} cannot hold one ray", backend, limit));
  ensure(static_cast<std::size_t>(chunk), layout);
  double seconds = 0.0;
  for (std::size_t first = 0; first < rays.size(); first += chunk) {
    std::size_t n = std::min<std::size_t>(chunk, rays.size() - first);
    rays_.upload(rays.data() + first, n * sizeof(kernel::Ray));
    kernel::TraceParams pc{static_cast<int>(n), param, 0, 0};
    auto groups = static_cast<std::uint32_t>((n + local_size - 1) / local_size);
    seconds += layout.dispatch(pipeline, &pc, groups);
    hits_.download(hits.data() + first, n * sizeof(kernel::Hit));
    if (!stats.empty()) stats_.download(stats.data() + first, n * sizeof(kernel::RayStats));
  }
  return seconds;
}

} // namespace masq::vk
