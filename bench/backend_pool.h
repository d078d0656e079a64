// Backends opened once per bench run and reused by every scene and suite: opening a
// Vulkan device or an OpenCL context, and compiling a kernel variant, is paid once
// (and reported as compile time on first use), not once per table cell. A backend may be
// opened several times (slots): each holds its own uploaded scene, so the bench can time
// several methods' structures round by round without uploading them again.
#pragma once
#include "host/backend.h"
#include <map>
#include <memory>
#include <string>
#include <utility>

namespace masq {

class BackendPool {
 public:
  // The backend in `slot`, opened on first use; nullptr when it cannot run here (why()
  // says why).
  Backend* get(const std::string& name, int slot = 0);
  std::string why(const std::string& name) const; // "" when available or not yet asked
  // Closes the backend in `slot` (its device, scene and compiled variants): lavapipe
  // maps memory per device and acceleration structure, and a process may hold only
  // vm.max_map_count mappings, so slots a bench no longer needs are given back.
  void close(const std::string& name, int slot);
 private:
  std::map<std::pair<std::string, int>, std::unique_ptr<Backend>> open_;
  std::map<std::string, std::string> unavailable_;
};

} // namespace masq
