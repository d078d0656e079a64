#include "bench/backend_pool.h"

namespace masq {

Backend* BackendPool::get(const std::string& name, int slot) {
  const std::pair<std::string, int> key{name, slot};
  if (auto it = open_.find(key); it != open_.end()) return it->second.get();
  if (unavailable_.count(name)) return nullptr;
  try {
    return (open_[key] = make_backend(name)).get();
  } catch (const std::exception& e) {
    open_.erase(key);
    unavailable_[name] = e.what();
    return nullptr;
  }
}

void BackendPool::close(const std::string& name, int slot) { open_.erase({name, slot}); }

std::string BackendPool::why(const std::string& name) const {
  auto it = unavailable_.find(name);
  return it == unavailable_.end() ? std::string() : it->second;
}

} // namespace masq
