#include "host/stack_size.h"
#include "host/kernel_variant.h"
#include "masq/error.h"
#include <string>

namespace masq {

namespace {

constexpr bool sizes_ascend() {
  for (std::size_t i = 1; i < kStackSizes.size(); ++i)
    if (kStackSizes[i] <= kStackSizes[i - 1]) return false;
  return kStackSizes.front() > 0;
}
static_assert(sizes_ascend(), "host/stack_size.h: kStackSizes must ascend from a positive size");
static_assert(kStackSizes.back() == MASQ_STACK_MAX, "host/stack_size.h: the largest size must be MASQ_STACK_MAX");
// The table's default (a kernel compiled without the host's choice, the cpu's stacks)
// must be the largest size, or a scene of unknown need could overflow.
static_assert(KernelVariant{}.tlas_stack == MASQ_STACK_MAX && KernelVariant{}.blas_stack == MASQ_STACK_MAX,
              "kernels/variant_table.h: the stack rows' default must be MASQ_STACK_MAX");

} // namespace

std::int32_t kernel_stack_size(int entries, const char* tree) {
  for (std::int32_t s : kStackSizes)
    if (entries <= s) return s;
  throw Error(std::string("kernel stack: the scene's ") + tree + " traversal needs " + std::to_string(entries) +
              " stack entries; the kernels hold at most " + std::to_string(kStackSizes.back()));
}

} // namespace masq
