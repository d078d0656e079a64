// The size a kernel's traversal stack is compiled with, from its scene's worst case
// (StackNeed, bvh/packed_scene.h): rounded up to one of a few sizes, so a handful of
// variants covers every scene while a shallow scene's GPU threads carry a small stack
// (each entry is a node index and its entry distance: 8 bytes per entry and stack).
#pragma once
#include <array>
#include <cstdint>

namespace masq {

// The sizes, ascending; the last is MASQ_STACK_MAX (kernels/variant_table.h).
inline constexpr std::array<std::int32_t, 6> kStackSizes{8, 16, 24, 32, 48, 64};

// The smallest size holding `entries` (tree: which walk, for the error). Throws
// masq::Error naming the need and the largest size if no size holds it: a stack that
// small would silently drop nodes and miss hits.
std::int32_t kernel_stack_size(int entries, const char* tree);

// Bytes of both traversal stacks of one thread (node index and distance per entry).
inline std::int64_t stack_bytes(std::int32_t tlas_size, std::int32_t blas_size) {
  return std::int64_t(tlas_size + blas_size) * 8;
}

} // namespace masq
