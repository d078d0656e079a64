#include "scenes/huge_page_vector.h"
#include "masq/knobs.h"
#include <cstdint>
#include <cstdlib>
#include <deque>
#include <mutex>
#include <iterator>
#if defined(__unix__) || defined(__APPLE__)
#include <sys/mman.h>
#endif

namespace masq {

namespace {
std::uintptr_t to_huge_page(std::uintptr_t n) { return (n + kHugePageBytes - 1) / kHugePageBytes * kHugePageBytes; }
std::size_t whole_huge_pages(std::size_t bytes) { return std::size_t(to_huge_page(bytes)); }
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
  const std::uintptr_t start = to_huge_page(first);
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
// them in the cpu backend's copy of each scene). A kept mapping serves an array of its
// own size in huge pages, so a mapping's size is always its array's, rounded. At most
// kKeptBytes are kept: freeing one more gives back the longest-kept ones first, so the
// kept sizes follow what the process builds now. Never destroyed (arrays of static
// storage may be freed after it would be).
class KeptMappings {
 public:
  static constexpr std::size_t kKeptBytes = std::size_t(256) << 20;

  void* take(std::size_t size) {
    std::lock_guard<std::mutex> lock(mutex_);
    for (auto it = kept_.rbegin(); it != kept_.rend(); ++it) // the most recently kept first
      if (it->size == size) {
        void* p = it->start;
        kept_bytes_ -= size;
        kept_.erase(std::next(it).base());
        return p;
      }
    return nullptr;
  }
  void release(void* p, std::size_t size) noexcept {
    std::lock_guard<std::mutex> lock(mutex_);
    if (size > kKeptBytes) {
      munmap(p, size);
      return;
    }
    while (kept_bytes_ + size > kKeptBytes) { // the longest kept go first
      munmap(kept_.front().start, kept_.front().size);
      kept_bytes_ -= kept_.front().size;
      kept_.pop_front();
    }
    try {
      kept_.push_back({p, size});
      kept_bytes_ += size;
    } catch (...) { // no room to remember it: give it back instead
      munmap(p, size);
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
};

KeptMappings& kept_mappings() {
  static KeptMappings* kept = new KeptMappings;
  return *kept;
}

} // namespace

void* map_huge_pages(std::size_t bytes) {
  const std::size_t size = whole_huge_pages(bytes);
  if (void* p = kept_mappings().take(size)) return p;
  return fresh_mapping(size);
}

void unmap_huge_pages(void* p, std::size_t bytes) noexcept { kept_mappings().release(p, whole_huge_pages(bytes)); }

#else

void* map_huge_pages(std::size_t bytes) {
  return ::operator new(whole_huge_pages(bytes), std::align_val_t(kHugePageBytes));
}
void unmap_huge_pages(void* p, std::size_t) noexcept { ::operator delete(p, std::align_val_t(kHugePageBytes)); }

#endif

} // namespace masq
