// Objects that every backend on one Context shares, made once per device rather than once
// per backend: pipeline layouts and pipelines. A bench opens a backend several times
// (slots, bench/backend_pool.h: one per method it times side by side, one per candidate
// of auto's pilot), and lavapipe compiles each pipeline with LLVM for about a second; with
// a pipeline per backend object, every slot compiled its own copy of the same variant.
#pragma once
#include <compare>
#include <cstddef>
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <vector>

namespace masq::vk {

class SharedObjects {
 public:
  // What tells two objects apart: who makes them (the address of a SPIR-V module or of a
  // tag of the kind of object) and the values they are made from (specialization
  // constants, descriptor types...).
  struct Key {
    const void* maker = nullptr;
    std::vector<std::uint32_t> values;
    auto operator<=>(const Key&) const = default;
  };

  // The object under `key`, made by `make()` (a std::shared_ptr to a T) on first use. The
  // lock is held while it is made, so that two threads asking at once make it once; a
  // `make` that throws leaves nothing behind. Every caller of one key asks for one T.
  template <class T, class Make>
  std::shared_ptr<const T> get(const Key& key, Make&& make) {
    std::lock_guard<std::mutex> lock(mutex_);
    auto it = objects_.find(key);
    if (it == objects_.end()) {
      std::shared_ptr<const T> made = make();
      it = objects_.emplace(key, std::move(made)).first;
    }
    return std::static_pointer_cast<const T>(it->second);
  }

  std::size_t size() {
    std::lock_guard<std::mutex> lock(mutex_);
    return objects_.size();
  }

 private:
  std::mutex mutex_;
  std::map<Key, std::shared_ptr<const void>> objects_;
};

} // namespace masq::vk
