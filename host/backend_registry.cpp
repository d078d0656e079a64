#include "host/backend.h"
#include "host/cpu/cpu_backend.h"
#include "host/opencl/opencl_backend.h"
#include "host/vulkan/vulkan_backends.h"
#include "scenes/error.h"

namespace masq {

const std::vector<std::string>& backend_names() {
  static const std::vector<std::string> names{"cpu", "vulkan", "opencl", "rayquery"};
  return names;
}

std::unique_ptr<Backend> make_backend(std::string_view name) {
  if (name == "cpu") return make_cpu_backend();
  if (name == "vulkan") return make_vulkan_backend();
  if (name == "opencl") return make_opencl_backend();
  if (name == "rayquery") return make_rayquery_backend();
  throw Error("unknown backend '" + std::string(name) + "' (expected cpu, vulkan, opencl or rayquery)");
}

} // namespace masq
