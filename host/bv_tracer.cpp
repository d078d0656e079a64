#include "host/bv_tracer.h"
#include "scenes/error.h"

namespace masq {

const std::vector<std::string>& bv_backend_names() {
  static const std::vector<std::string> names{"cpu", "vulkan", "opencl"};
  return names;
}

std::unique_ptr<BvTracer> make_bv_tracer(std::string_view name) {
  if (name == "cpu") return make_cpu_bv_tracer();
  if (name == "vulkan") return make_vulkan_bv_tracer();
  if (name == "opencl") return make_opencl_bv_tracer();
  throw Error("bv: unknown backend '" + std::string(name) + "' (expected cpu, vulkan or opencl)");
}

} // namespace masq
