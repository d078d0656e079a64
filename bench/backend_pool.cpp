#include "bench/backend_pool.h"

namespace masq {

Backend* BackendPool::get(const std::string& name) {
  if (auto it = open_.find(name); it != open_.end()) return it->second.get();
  if (unavailable_.count(name)) return nullptr;
  try {
    return (open_[name] = make_backend(name)).get();
  } catch (const std::exception& e) {
    open_.erase(name);
    unavailable_[name] = e.what();
    return nullptr;
  }
}

std::string BackendPool::why(const std::string& name) const {
  auto it = unavailable_.find(name);
  return it == unavailable_.end() ? std::string() : it->second;
}

} // namespace masq
