// The backend registry: the one list of backends. Names, `masq info`, the CLI's
// choices, the bench's defaults, "best" and the bv tracers all read backend_table.
#include "host/backend.h"
#include "host/bv_tracer.h"
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

std::unique_ptr<Backend> make_best_backend() {
  std::vector<const BackendRow*> ranked;
  for (const BackendRow& r : backend_table.rows())
    if (r.best_rank > 0) ranked.push_back(&r);
  std::sort(ranked.begin(), ranked.end(),
            [](const BackendRow* a, const BackendRow* b) { return a->best_rank < b->best_rank; });
  std::string why;
  for (const BackendRow* r : ranked) {
    try {
      return r->make();
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
