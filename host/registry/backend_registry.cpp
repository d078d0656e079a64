// The backend registry: the one list of backends. Names, `masq info`, the CLI's
// choices, the bench's defaults, "best" and the bv tracers all read backend_table.
#include "host/backend.h"
#include "host/bv_tracer.h"
#include "host/device_list.h"
#include "host/cpu/cpu_backend.h"
#include "host/opencl/opencl_backend.h"
#include "host/vulkan/vulkan_backends.h"
#include "masq/error.h"
#include <algorithm>

namespace masq {

namespace {

constexpr BackendRow backend_rows[] = {
    {"cpu", "the kernel source compiled as C++, multi-threaded", make_cpu_backend, make_cpu_bv_tracer, 3, nullptr, false},
    {"vulkan", "the kernel source as GLSL compute shaders", make_vulkan_backend, make_vulkan_bv_tracer, 1, "vulkan",
     false},
    {"opencl", "the kernel source as OpenCL C", [] { return make_opencl_backend(); }, make_opencl_bv_tracer, 2, "opencl",
     false},
    {"rayquery", "Vulkan ray query on the driver's own acceleration structures", make_rayquery_backend, nullptr, 0,
     "rayquery", true},
    {"rtpipeline", "the Vulkan ray-tracing pipeline: the driver's acceleration structures call masq's intersectors as "
                   "intersection shaders", make_rtpipeline_backend, nullptr, 0, "rtpipeline", true},
};

bool has_bv(const BackendRow& r) { return r.make_bv != nullptr; }

} // namespace

constinit const NameTable<BackendRow> backend_table{"backend", backend_rows};

const std::vector<std::string>& backend_names() {
  static const std::vector<std::string> names = backend_table.names();
  return names;
}

bool driver_traversal(std::string_view backend) {
  const BackendRow* r = backend_table.find(backend);
  return r && r->driver_traversal;
}

std::unique_ptr<Backend> make_backend(std::string_view name) { return backend_table.at(name).make(); }

namespace {
// Whether the device backend `r` would open runs on the host's own cores (lavapipe, PoCL's
// CPU device): the cpu backend runs the same kernels natively there, without a driver's
// compile (issue 40: Context("best") took lavapipe, 3 s of shader compile, then 6x slower).
bool on_host_cores(const BackendRow& r, const std::vector<ApiDevices>& apis) {
  if (!r.device_api) return false;
  for (const ApiDevices& a : apis)
    for (const auto& [backend, choice] : a.picks)
      if (backend == r.name && choice.position >= 0)
        return a.devices.at(std::size_t(choice.position)).type == DeviceType::Cpu;
  return false; // no device listed: opening it says why
}
} // namespace

std::vector<std::string> best_backend_order() {
  const std::vector<ApiDevices> apis = list_devices();
  std::vector<std::pair<int, const BackendRow*>> ranked; // (tier, row): real devices, cpu, software devices
  for (const BackendRow& r : backend_table.rows())
    if (r.best_rank > 0) ranked.emplace_back(on_host_cores(r, apis) ? 1 : 0, &r);
  std::stable_sort(ranked.begin(), ranked.end(), [](const auto& a, const auto& b) {
    return a.first != b.first ? a.first < b.first : a.second->best_rank < b.second->best_rank;
  });
  std::vector<std::string> names;
  for (const auto& [tier, r] : ranked) names.push_back(r->name);
  return names;
}

std::unique_ptr<Backend> make_best_backend() {
  std::string why;
  for (const std::string& name : best_backend_order()) {
    try {
      return backend_table.at(name).make();
    } catch (const BackendUnavailable& e) {
      why += (why.empty() ? "" : "; ") + std::string(e.what());
    }
  }
  throw BackendUnavailable("best: no backend opens here (" + why + ")");
}

const std::vector<std::string>& bv_backend_names() {
  static const std::vector<std::string> names = backend_table.names(has_bv);
  return names;
}

std::unique_ptr<BvTracer> make_bv_tracer(std::string_view name) {
  const BackendRow* r = backend_table.find(name);
  if (!r || !has_bv(*r))
    throw Error("unknown bv backend '" + std::string(name) + "' (expected " + backend_table.choices(has_bv) + ")");
  return r->make_bv();
}

} // namespace masq
