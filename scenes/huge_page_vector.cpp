#include "scenes/huge_page_vector.h"
#include "masq/knobs.h"
#include <cstdint>
#include <cstdlib>
#include <deque>
#include <mutex>
#include <unordered_map>
#if defined(__unix__) || defined(__APPLE__)
#include <sys/mman.h>
#endif

namespace masq {

namespace {
std::size_t whole_huge_pages(std::size_t bytes) { return (bytes + kHugePageBytes - 1) / kHugePageBytes * kHugePageBytes; }
} // namespace

bool huge_pages_on() {
  static const bool on = knob_choice(Knob::HugePages, "host memory") == "on";
  return on;
}

#if defined(__unix__) || defined(__APPLE__)

namespace {

// A fresh mapping of size bytes (whole huge pages), 2 MiB aligned and advised.
void* fresh_mapping(std::size_t size) {
  // mmap aligns to 4 KiB only, and the kernel backs only whole aligned 2 MiB extents
  // with a huge page: map one huge page more and give back the head and the tail.
  void* raw = mmap(nullptr, size + kHugePageBytes, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
  if (raw == MAP_FAILED) throw std::bad_alloc();
  const std::uintptr_t first = reinterpret_cast<std::uintptr_t>(raw);
  const std::uintptr_t start = (first + kHugePageBytes - 1) / kHugePageBytes * kHugePageBytes;
  if (start > first) munmap(raw, start - first);
  const std::uintptr_t end = first + size + kHugePageBytes;
  if (end > start + size) munmap(reinterpret_cast<void*>(start + size), end - (start + size));
#ifdef MADV_HUGEPAGE
  madvise(reinterpret_cast<void*>(start), size, MADV_HUGEPAGE); // advice: refused, the pages are 4 KiB ones
#endif
  return reinterpret_cast<void*>(start);
}

// Mappings a finished build freed, kept for the next one: a scene's arrays have the same
// sizes build after build, and a kept mapping is neither faulted nor zeroed again (the
// kernel zeroes every fresh huge page: 6.6% of the quick peers suite's samples, most of
// them in the cpu backend's copy of each scene). A kept mapping serves a request of at
// least half its size. At most kKeptBytes are kept: freeing one more gives back the
// longest-kept ones first, so the kept sizes follow what the process builds now. Never
// destroyed (arrays of static storage may be freed after it would be).
class KeptMappings {
 public:
  static constexpr std::size_t kKeptBytes = std::size_t(256) << 20;

  void* take(std::size_t size) {
    std::lock_guard<std::mutex> lock(mutex_);
    // The smallest kept mapping that holds size and wastes at most half of itself.
    auto best = kept_.end();
    for (auto it = kept_.begin(); it != kept_.end(); ++it)
      if (it->size >= size && it->size <= 2 * size && (best == kept_.end() || it->size < best->size)) best = it;
    if (best == kept_.end()) return nullptr;
    void* p = best->start;
    size_of_[p] = best->size;
    kept_bytes_ -= best->size;
    kept_.erase(best);
    return p;
  }
  void mapped(void* p, std::size_t size) {
    std::lock_guard<std::mutex> lock(mutex_);
    size_of_[p] = size;
  }
  void release(void* p) noexcept {
    std::lock_guard<std::mutex> lock(mutex_);
    auto it = size_of_.find(p);
    if (it == size_of_.end()) return; // not one of ours: nothing to free
    const Mapping m{p, it->second};
    size_of_.erase(it);
    if (m.size > kKeptBytes) {
      munmap(m.start, m.size);
      return;
    }
    while (kept_bytes_ + m.size > kKeptBytes) { // the longest kept go first
      munmap(kept_.front().start, kept_.front().size);
      kept_bytes_ -= kept_.front().size;
      kept_.pop_front();
    }
    try {
      kept_.push_back(m);
      kept_bytes_ += m.size;
    } catch (...) { // no room to remember it: give it back instead
      munmap(m.start, m.size);
    }
  }

 private:
  struct Mapping {
    void* start;
    std::size_t size;
  };
  std::mutex mutex_;
  std::deque<Mapping> kept_; // in the order they were freed
  std::size_t kept_bytes_ = 0;
  std::unordered_map<void*, std::size_t> size_of_; // every mapping handed out: its size
};

KeptMappings& kept_mappings() {
  static KeptMappings* kept = new KeptMappings;
  return *kept;
}

} // namespace

void* map_huge_pages(std::size_t bytes) {
  const std::size_t size = whole_huge_pages(bytes);
  if (void* p = kept_mappings().take(size)) return p;
  void* p = fresh_mapping(size);
  try {
    kept_mappings().mapped(p, size);
  } catch (...) {
    munmap(p, size);
    throw;
  }
  return p;
}

void unmap_huge_pages(void* p, std::size_t) noexcept { kept_mappings().release(p); }

#else

void* map_huge_pages(std::size_t bytes) {
  return ::operator new(whole_huge_pages(bytes), std::align_val_t(kHugePageBytes));
}
void unmap_huge_pages(void* p, std::size_t) noexcept { ::operator delete(p, std::align_val_t(kHugePageBytes)); }

#endif

} // namespace masq
