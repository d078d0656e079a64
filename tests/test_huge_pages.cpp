// scenes/huge_page_vector.h: arrays of 2 MiB or more on their own 2 MiB-aligned mapping,
// advised MADV_HUGEPAGE; smaller ones from std::allocator. The contents are what a
// std::vector would hold through growth, copies, moves and swaps, and the knob
// (MASQ_HUGE_PAGES, read once per process) leaves the default on.
#include "scenes/huge_page_vector.h"
#include <gtest/gtest.h>
#include <cstdint>
#include <fstream>
#include <numeric>
#include <sstream>
#include <string>

using namespace masq;

namespace {

bool aligned_to_huge_page(const void* p) { return reinterpret_cast<std::uintptr_t>(p) % kHugePageBytes == 0; }

// The VmFlags line of the /proc/self/smaps entry holding p ("" when none is found).
std::string vm_flags_of(const void* p) {
  std::ifstream smaps("/proc/self/smaps");
  const std::uintptr_t a = reinterpret_cast<std::uintptr_t>(p);
  std::string line;
  bool inside = false;
  while (std::getline(smaps, line)) {
    std::uintptr_t lo = 0, hi = 0;
    char dash = 0;
    std::istringstream head(line);
    if (head >> std::hex >> lo >> dash >> hi && dash == '-') inside = lo <= a && a < hi;
    else if (inside && line.rfind("VmFlags:", 0) == 0) return line;
  }
  return "";
}

} // namespace

TEST(HugePages, SmallArraysComeFromTheOrdinaryAllocator) {
  HugePageVector<int> v(1000);
  std::iota(v.begin(), v.end(), 0);
  EXPECT_EQ(v[999], 999);
  // std::allocator's heap, which nobody advised: no "hg" among its mapping's flags.
  if (std::ifstream("/sys/kernel/mm/transparent_hugepage/enabled")) {
    const std::string flags = vm_flags_of(v.data());
    ASSERT_FALSE(flags.empty()) << "no /proc/self/smaps entry holds the array";
    EXPECT_EQ(flags.find(" hg"), std::string::npos) << flags;
  }
}

TEST(HugePages, LargeArraysAreAlignedAdvisedAndKeepTheirContents) {
  ASSERT_TRUE(huge_pages_on()) << "MASQ_HUGE_PAGES is on unless set to off";
  HugePageVector<std::uint32_t> v;
  // Growth by push_back crosses the threshold: each reallocation keeps the contents.
  const std::size_t n = 3 * kHugePageBytes / sizeof(std::uint32_t) + 17;
  for (std::size_t i = 0; i < n; ++i) v.push_back(std::uint32_t(i * 2654435761u));
  ASSERT_GE(v.capacity() * sizeof(std::uint32_t), kHugePageBytes);
  EXPECT_TRUE(aligned_to_huge_page(v.data()));
  for (std::size_t i = 0; i < n; i += 4099) ASSERT_EQ(v[i], std::uint32_t(i * 2654435761u)) << i;
  EXPECT_EQ(v.back(), std::uint32_t((n - 1) * 2654435761u));

  // Where the kernel has transparent huge pages, the mapping carries the advice ("hg").
  if (std::ifstream("/sys/kernel/mm/transparent_hugepage/enabled")) {
    const std::string flags = vm_flags_of(v.data());
    ASSERT_FALSE(flags.empty()) << "no /proc/self/smaps entry holds the array";
    EXPECT_NE(flags.find(" hg"), std::string::npos) << flags;
  }

  // Copy, move and swap: the same elements; a move hands the buffer over.
  HugePageVector<std::uint32_t> copy = v;
  EXPECT_TRUE(copy == v);
  EXPECT_TRUE(aligned_to_huge_page(copy.data()));
  const std::uint32_t* buffer = copy.data();
  HugePageVector<std::uint32_t> moved = std::move(copy);
  EXPECT_EQ(moved.data(), buffer);
  HugePageVector<std::uint32_t> small(5, 7u);
  small.swap(moved);
  EXPECT_EQ(small.data(), buffer);
  EXPECT_EQ(moved.size(), 5u);
  EXPECT_TRUE(small == v);

  // Shrinking below the threshold (a copy of a few elements) goes back to std::allocator
  // and frees the mapping the way it was made.
  v.resize(10);
  v.shrink_to_fit();
  EXPECT_EQ(v.size(), 10u);
  EXPECT_EQ(v[9], std::uint32_t(9 * 2654435761u));
}

TEST(HugePages, OverAlignedElementsKeepTheirAlignment) {
  struct alignas(64) Line {
    float f[16];
  };
  HugePageVector<Line> few(3), many(kHugePageBytes / sizeof(Line) + 1);
  EXPECT_EQ(reinterpret_cast<std::uintptr_t>(few.data()) % 64, 0u);
  EXPECT_TRUE(aligned_to_huge_page(many.data()));
  many.back().f[15] = 1.5f;
  EXPECT_EQ(many.back().f[15], 1.5f);
}
