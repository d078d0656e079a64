// Accel and Context: the public face of build_accel (bvh/) and of the backends (host/).
#include "api/api_impl.h"
#include "host/backend.h"
#include "host/device_choice.h"
#include "masq/masq.h"
#include <cstddef>
#include <cstring>
#include <mutex>

namespace masq::api {

// Public rays, hits and counters cross into the kernels by memcpy: the layouts must be
// the kernels' own (kernels/layout.h).
static_assert(sizeof(Ray) == sizeof(kernel::Ray) && offsetof(Ray, tmin) == offsetof(kernel::Ray, tmin) &&
              offsetof(Ray, dir) == offsetof(kernel::Ray, dir) && offsetof(Ray, tmax) == offsetof(kernel::Ray, tmax));
static_assert(sizeof(Hit) == sizeof(kernel::Hit) && offsetof(Hit, prim) == offsetof(kernel::Hit, prim) &&
              offsetof(Hit, geometry) == offsetof(kernel::Hit, geom) &&
              offsetof(Hit, instance) == offsetof(kernel::Hit, inst) &&
              offsetof(Hit, normal) == offsetof(kernel::Hit, normal) && offsetof(Hit, u) == offsetof(kernel::Hit, u));
static_assert(sizeof(RayStats) == sizeof(kernel::RayStats) &&
              offsetof(RayStats, isect_calls) == offsetof(kernel::RayStats, isect_calls));

const char* version() { return MASQ_VERSION; }

Accel Accel::build(const Scene& scene, const AccelOptions& options) {
  masq::Scene s = scene.impl().placed();
  validate_scene(s);
  AccelOptions o = options;
  // The public option enums are the builder's own (bvh/options.h): they pass as they
  // are, once known to be values of their tables (row() throws masq::Error otherwise).
  method_table.row(options.method);
  mode_table.row(options.mode);
  curve_isect_table.row(options.curve_isect);
  builder_table.row(options.builder);
  node_format_table.row(options.nodes);
  blas_occlusion_table.row(options.blas_occlusion);
  masq::AccelOptions ao;
  ao.mode = options.mode;
  ao.curve_isect = options.curve_isect;
  ao.builder.kind = options.builder;
  ao.nodes = options.nodes;
  ao.masq_instances = options.compact_masquerade ? masq::MasqInstances::Compact : masq::MasqInstances::Full;
  ao.build_threads = options.build_threads;
  ao.blas_occlusion = options.blas_occlusion;
  auto impl = std::make_shared<Impl>();
  impl->packed = build_accel(s, options.method, ao);
  impl->options = o;
  impl->primitives = s.primitive_count();
  Accel a;
  a.impl_ = std::move(impl);
  return a;
}

AccelStats Accel::stats() const {
  if (!impl_) throw Error("Accel::stats: the Accel was not built (use Accel::build)");
  const PackedScene& p = impl_->packed;
  // auto marks its structure Method::Auto and records the candidate it kept
  // (bvh/twolevel/build_accel.h, mark_as_auto); the kept one is what callers ask about.
  const Method kept = p.method == Method::Auto ? p.stats.auto_choice : p.method;
  return {p.stats.instances, p.stats.tlas_nodes, p.stats.blas_nodes, p.acceleration_bytes() + p.primitive_bytes(),
          p.stats.node_bytes, p.stats.build_seconds, kept, impl_->primitives};
}

AccelOptions Accel::options() const {
  if (!impl_) throw Error("Accel::options: the Accel was not built (use Accel::build)");
  return impl_->options;
}

struct Context::Impl {
  std::unique_ptr<Backend> backend;
  std::shared_ptr<const Accel::Impl> uploaded; // held so its address cannot be reused by another Accel
  std::vector<kernel::Ray> rays;               // staging, reused between traces
  std::vector<kernel::Hit> hits;
  std::vector<kernel::RayStats> stats;

  void run(const Accel& accel, std::span<const Ray> in_rays, std::span<Hit> out_hits, std::span<RayStats> stats_out,
           Query query, const char* what);
};

Context::Context(const std::string& backend) : impl_(std::make_unique<Impl>()) {
  impl_->backend = backend == "best" ? make_best_backend() : make_backend(backend);
}

Context::Context(const std::string& backend, const std::string& device) : impl_(std::make_unique<Impl>()) {
  if (device.empty()) {
    impl_->backend = backend == "best" ? make_best_backend() : make_backend(backend);
    return;
  }
  const BackendRow* row = backend == "best" ? nullptr : &backend_table.at(backend);
  if (!row || !row->device_api)
    throw Error("Context: device '" + device + "' given for the " + backend +
                " backend, which has no device to choose (name one of " +
                backend_table.choices([](const BackendRow& r) { return r.device_api != nullptr; }) + ")");
  // The selectors are process-wide (host/device_choice.h): this one is set while the
  // backend opens its device and the previous one put back after, so it holds for this
  // Context only.
  static std::mutex selector_mutex;
  std::lock_guard<std::mutex> lock(selector_mutex);
  const DeviceApi api = device_api_table.parse(row->device_api);
  const DeviceSelector before = device_selector(api);
  const bool before_was_override = before.source != knob_name(device_api_table.row(api).knob);
  set_device_selector(api, device, "Context device");
  try {
    impl_->backend = make_backend(backend);
  } catch (...) {
    set_device_selector(api, before_was_override ? before.value : "", before.source);
    throw;
  }
  set_device_selector(api, before_was_override ? before.value : "", before.source);
}

Context::~Context() = default;
Context::Context(Context&&) noexcept = default;
Context& Context::operator=(Context&&) noexcept = default;

std::vector<std::string> Context::backends() { return backend_names(); }

std::vector<std::string> Context::available_backends() {
  std::vector<std::string> out;
  for (const std::string& name : backend_names()) {
    try {
      make_backend(name);
      out.push_back(name);
    } catch (const BackendUnavailable&) {
    }
  }
  return out;
}

std::string Context::backend() const { return impl_ ? impl_->backend->name() : std::string(); }
std::string Context::device() const { return impl_ ? impl_->backend->device_name() : std::string(); }

// One batch through the backend: the public structs cross by memcpy (layouts asserted
// equal above; the public ones are not trivially default-constructible, hence void*).
void Context::Impl::run(const Accel& accel, std::span<const Ray> in_rays, std::span<Hit> out_hits,
                        std::span<RayStats> stats_out, Query query, const char* what) {
  Impl& m = *this;
  if (!accel.impl()) throw Error(std::string(what) + ": the Accel was not built (use Accel::build)");
  if (m.uploaded != accel.impl()) {
    m.uploaded.reset(); // a failed upload must not leave a stale Accel marked current
    m.backend->set_scene(accel.impl()->packed);
    m.uploaded = accel.impl();
  }
  m.rays.resize(in_rays.size());
  m.hits.resize(in_rays.size());
  m.stats.resize(stats_out.size());
  if (!in_rays.empty()) std::memcpy(static_cast<void*>(m.rays.data()), in_rays.data(), in_rays.size_bytes());
  m.backend->trace(m.rays, m.hits, m.stats, query);
  if (!in_rays.empty()) std::memcpy(static_cast<void*>(out_hits.data()), m.hits.data(), out_hits.size_bytes());
  if (!stats_out.empty()) std::memcpy(static_cast<void*>(stats_out.data()), m.stats.data(), stats_out.size_bytes());
}

void Context::trace(const Accel& accel, std::span<const Ray> rays, std::span<Hit> hits, std::span<RayStats> stats) {
  if (!impl_) throw Error("Context::trace: the Context was moved from");
  if (hits.size() != rays.size())
    throw Error("Context::trace: " + std::to_string(rays.size()) + " rays but room for " +
                std::to_string(hits.size()) + " hits");
  if (!stats.empty() && stats.size() != rays.size())
    throw Error("Context::trace: " + std::to_string(rays.size()) + " rays but " + std::to_string(stats.size()) +
                " stats entries (give none or one per ray)");
  impl_->run(accel, rays, hits, stats, Query::Closest, "Context::trace");
}

std::vector<Hit> Context::trace(const Accel& accel, std::span<const Ray> rays) {
  std::vector<Hit> hits(rays.size());
  trace(accel, rays, hits);
  return hits;
}

void Context::occluded(const Accel& accel, std::span<const Ray> rays, std::span<std::uint8_t> occluded) {
  if (!impl_) throw Error("Context::occluded: the Context was moved from");
  if (occluded.size() != rays.size())
    throw Error("Context::occluded: " + std::to_string(rays.size()) + " rays but room for " +
                std::to_string(occluded.size()) + " results");
  std::vector<Hit> hits(rays.size());
  impl_->run(accel, rays, hits, {}, Query::Any, "Context::occluded");
  for (std::size_t i = 0; i < hits.size(); ++i) occluded[i] = hits[i].hit() ? 1 : 0;
}

Timing Context::timing() const {
  if (!impl_) return {};
  TraceTiming t = impl_->backend->timing();
  return {t.scene_seconds, t.compile_seconds, t.trace_seconds};
}

std::size_t Context::device_bytes() const { return impl_ ? impl_->backend->device_bytes() : 0; }

} // namespace masq::api
