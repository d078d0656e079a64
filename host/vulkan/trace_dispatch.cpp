#include "host/vulkan/trace_dispatch.h"
#include "host/limit_knob.h"
#include "kernels/kernel_data.h"
#include <fmt/format.h>
#include <algorithm>
#include <chrono>

namespace masq::vk {

void check_storage_range(const Context& ctx, const char* backend, const char* what, std::uint64_t bytes) {
  std::uint64_t limit = ctx.max_storage_buffer_range();
  if (bytes > limit)
    throw Error(fmt::format("{}: {} needs {} bytes in one storage buffer; the device allows {} "
                            "(maxStorageBufferRange)",
                            backend, what, bytes, limit));
}

std::vector<VkDescriptorType> kernel_descriptor_types() {
  std::vector<VkDescriptorType> t(MASQ_BINDING_ADDRESSES + 1, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER);
  t[MASQ_BINDING_ADDRESSES] = VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER;
  return t;
}

void SceneBuffers::add(Context& ctx, const char* backend, std::uint32_t binding, const char* what,
                       std::uint64_t size, const std::function<void(Buffer&)>& fill) {
  if (binding >= MASQ_ADDRESS_SLOTS) throw Error(fmt::format("{}: {} has binding {}", backend, what, binding));
  std::uint64_t limit = ctx.max_allocation_bytes();
  if (size > limit)
    throw Error(fmt::format("{}: {} needs {} bytes in one buffer; the device allows {} ({})", backend, what, size,
                            limit, ctx.max_allocation_name()));
  VkBufferUsageFlags usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
  if (ctx.buffer_device_address()) usage |= VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT;
  Array a;
  try {
    a.buffer = Buffer(ctx, size, usage);
  } catch (const Error& e) { // e.g. out of device memory: say for which array
    throw Error(fmt::format("{}: allocating {} ({} bytes): {}", backend, what, size, e.what()));
  }
  if (size > 0) fill(a.buffer);
  a.what = what;
  a.bytes = size;
  if (auto old = arrays_.find(binding); old != arrays_.end()) bytes -= old->second.bytes; // replaced
  arrays_[binding] = std::move(a);
  bytes += size;
}

void SceneBuffers::finish(Context& ctx, const char* backend, bool prefer_addressed) {
  std::uint64_t range = ctx.max_storage_buffer_range();
  const Array* largest = nullptr;
  for (const auto& [binding, a] : arrays_)
    if (largest == nullptr || a.bytes > largest->bytes) largest = &a;
  addressed_ = (largest != nullptr && largest->bytes > range) || (prefer_addressed && ctx.buffer_device_address());
  if (addressed_ && !ctx.buffer_device_address())
    check_storage_range(ctx, backend, largest->what.c_str(), largest->bytes);
  // std140: one 16-byte element per slot, the address in its first 8 bytes.
  std::vector<std::uint64_t> slots(2 * MASQ_ADDRESS_SLOTS, 0);
  if (addressed_)
    for (const auto& [binding, a] : arrays_) slots[2 * binding] = a.buffer.address();
  table_ = Buffer(ctx, slots.size() * sizeof(std::uint64_t), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT);
  table_.upload(slots.data(), slots.size() * sizeof(std::uint64_t));
  dummy_ = Buffer(ctx, 16, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
}

void SceneBuffers::bind(KernelLayout& layout) const {
  if (!table_.valid()) throw Error("vulkan: SceneBuffers bound before finish()");
  for (const auto& [binding, a] : arrays_) layout.bind_buffer(binding, addressed_ ? dummy_ : a.buffer);
  layout.bind_buffer(MASQ_BINDING_ADDRESSES, table_);
}

void add_scene_arrays(SceneBuffers& b, Context& ctx, const char* backend, const SceneArrayData& data,
                      KernelFamily family) {
  for (std::size_t i = 0; i < kSceneArrayCount; ++i) {
    const SceneArrayInfo& row = kSceneArrays[i];
    if (!row.read_by(family)) continue; // its binding stays unwritten: the kernel never reads it
    const ArrayBytes& d = data.rows[i];
    b.add(ctx, backend, row.binding, fmt::format("scene array '{}'", row.name).c_str(), d.bytes,
          [&](Buffer& buf) { buf.upload(d.data, d.bytes); });
  }
}

std::vector<std::uint32_t> spec_constants(const KernelVariant& v, std::uint32_t local_size) {
  std::uint32_t ids = MASQ_SPEC_LOCAL_SIZE + 1;
  for (const VariantSwitch& s : kVariantSwitches) ids = std::max(ids, s.spec_id + 1);
  std::vector<std::uint32_t> values(ids, 0);
  const auto row_values = switch_values(v);
  for (std::size_t i = 0; i < kVariantSwitchCount; ++i)
    values[kVariantSwitches[i].spec_id] = static_cast<std::uint32_t>(row_values[i]);
  values[MASQ_SPEC_LOCAL_SIZE] = local_size;
  return values;
}

void RayBatch::ensure(std::size_t capacity, KernelLayout& layout) {
  if (capacity > capacity_ || !rays_.valid()) {
    rays_ = Buffer(ctx_, capacity * sizeof(kernel::Ray), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, BufferRole::RayInput);
    hits_ = Buffer(ctx_, capacity * sizeof(kernel::Hit), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, BufferRole::Results);
    stats_ =
        Buffer(ctx_, capacity * sizeof(kernel::RayStats), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, BufferRole::Results);
    capacity_ = capacity;
  }
  layout.bind_buffer(MASQ_BINDING_RAYS, rays_);
  layout.bind_buffer(MASQ_BINDING_HITS, hits_);
  layout.bind_buffer(MASQ_BINDING_STATS, stats_);
}

void RayBatch::bind_minimal(KernelLayout& layout) { ensure(std::max<std::size_t>(capacity_, 1), layout); }

RayBatch::Times RayBatch::run(const char* backend, KernelLayout& layout, VkPipeline pipeline,
                              std::uint32_t local_size, std::int32_t param, std::span<const kernel::Ray> rays,
                              std::span<kernel::Hit> hits, std::span<kernel::RayStats> stats,
                              std::int32_t budget) {
  // The group count within the device's limit.
  const std::uint64_t max_launch = std::uint64_t(ctx_.props().limits.maxComputeWorkGroupCount[0]) * local_size;
  return run_chunks(backend, layout, max_launch, rays, hits, stats, [&](std::uint32_t n) {
    kernel::TraceParams pc{static_cast<int>(n), param, 0, budget};
    return layout.dispatch(pipeline, &pc, (n + local_size - 1) / local_size);
  });
}

RayBatch::Times RayBatch::run_chunks(const char* backend, KernelLayout& layout, std::uint64_t max_launch,
                                     std::span<const kernel::Ray> rays, std::span<kernel::Hit> hits,
                                     std::span<kernel::RayStats> stats,
                                     const std::function<double(std::uint32_t n)>& launch) {
  using Clock = std::chrono::steady_clock;
  auto since = [](Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); };
  const Clock::time_point start = Clock::now();
  if (hits.size() != rays.size())
    throw Error(fmt::format("{}: trace: {} rays but {} hits", backend, rays.size(), hits.size()));
  if (!stats.empty() && stats.size() != rays.size())
    throw Error(fmt::format("{}: trace: {} rays but {} stats", backend, rays.size(), stats.size()));
  Times times;
  if (rays.empty()) return times;
  // Chunk: every per-ray buffer within one binding, the launch within the device's limit,
  // the count within a push-constant int, and one launch short (the watchdog bound).
  std::uint64_t limit = ctx_.max_storage_buffer_range();
  std::uint64_t chunk = limit / sizeof(kernel::Hit);
  chunk = std::min<std::uint64_t>(chunk, limit / sizeof(kernel::Ray));
  chunk = std::min<std::uint64_t>(chunk, max_launch);
  chunk = std::min<std::uint64_t>(chunk, 1u << 30);
  chunk = std::min<std::uint64_t>(chunk, max_rays_per_dispatch(backend));
  chunk = std::min<std::uint64_t>(chunk, rays.size());
  if (chunk == 0) throw Error(fmt::format("{}: maxStorageBufferRange {} cannot hold one ray", backend, limit));
  ensure(static_cast<std::size_t>(chunk), layout);
  for (std::size_t first = 0; first < rays.size(); first += chunk) {
    std::size_t n = std::min<std::size_t>(chunk, rays.size() - first);
    Clock::time_point t0 = Clock::now();
    rays_.upload(rays.data() + first, n * sizeof(kernel::Ray));
    times.upload += since(t0);
    times.device += launch(static_cast<std::uint32_t>(n));
    t0 = Clock::now();
    hits_.download(hits.data() + first, n * sizeof(kernel::Hit));
    if (!stats.empty()) stats_.download(stats.data() + first, n * sizeof(kernel::RayStats));
    times.readback += since(t0);
  }
  times.wall = since(start);
  return times;
}

} // namespace masq::vk
