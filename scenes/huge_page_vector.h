// Large arrays on transparent huge pages. A build of the bear writes tens of MiB of fresh
// arrays (SAH references, binary nodes, boxes, the packed scene); on 4 KiB pages each
// page's first touch is a fault, and on these virtual machines the faults were a fifth to
// a third of a build's time (perf: the kernel's fault path; a build of Ratboy's capsules
// took half the time with the system's THP mode switched to "always"). An array of at
// least one huge page (2 MiB) is mapped on its own, aligned to 2 MiB, and advised
// MADV_HUGEPAGE, so that each 2 MiB is one fault: what Embree does with its large blocks
// (madvise in its os_malloc). The advice is only advice: where THP is off ("never"), or
// on systems without madvise, the pages are the ordinary ones, with the same contents.
#pragma once
#include <cstddef>
#include <memory>
#include <new>
#include <type_traits>
#include <vector>

namespace masq {

inline constexpr std::size_t kHugePageBytes = std::size_t(2) << 20;

// bytes (>= kHugePageBytes) rounded up to whole huge pages, 2 MiB aligned: a mapping an
// earlier array of that size freed (up to 256 MiB of them are kept,
// scenes/huge_page_vector.cpp), else a fresh one; throws std::bad_alloc when the system
// refuses. unmap_huge_pages takes the same bytes.
void* map_huge_pages(std::size_t bytes);
void unmap_huge_pages(void* p, std::size_t bytes) noexcept;
// MASQ_HUGE_PAGES (on unless set to off), read once per process: an array is freed the
// way it was allocated. Throws masq::Error for a bad value (at the first large array).
bool huge_pages_on();

// std::allocator below one huge page (or with MASQ_HUGE_PAGES=off), map_huge_pages from
// there (stateless: any two compare equal, so vectors move and swap their buffers as
// with std::allocator).
template <class T> struct HugePageAllocator {
  using value_type = T;
  using is_always_equal = std::true_type;
  HugePageAllocator() noexcept = default;
  template <class U> HugePageAllocator(const HugePageAllocator<U>&) noexcept {}

  T* allocate(std::size_t n) {
    static_assert(alignof(T) <= kHugePageBytes);
    if (n > std::size_t(-1) / sizeof(T)) throw std::bad_array_new_length();
    if (n * sizeof(T) >= kHugePageBytes && huge_pages_on()) return static_cast<T*>(map_huge_pages(n * sizeof(T)));
    return std::allocator<T>{}.allocate(n);
  }
  void deallocate(T* p, std::size_t n) noexcept {
    if (n * sizeof(T) >= kHugePageBytes && huge_pages_on()) unmap_huge_pages(p, n * sizeof(T));
    else std::allocator<T>{}.deallocate(p, n);
  }
  template <class U> bool operator==(const HugePageAllocator<U>&) const noexcept { return true; }
};

template <class T> using HugePageVector = std::vector<T, HugePageAllocator<T>>;

} // namespace masq
