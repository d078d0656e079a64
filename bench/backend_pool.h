// Backends opened once per bench run and reused by every scene and suite: opening a
// Vulkan device or an OpenCL context, and compiling a kernel variant, is paid once
// (and reported as compile time on first use), not once per table cell.
#pragma once
#include "host/backend.h"
#include <map>
#include <memory>
#include <string>

namespace masq {

class BackendPool {
 public:
  // The backend, opened on first use; nullptr when it cannot run here (why() says why).
  Backend* get(const std::string& name);
  std::string why(const std::string& name) const; // "" when available or not yet asked
 private:
  std::map<std::string, std::unique_ptr<Backend>> open_;
  std::map<std::string, std::string> unavailable_;
};

} // namespace masq
