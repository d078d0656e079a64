// Collapse a binary BVH into MASQ_WIDTH-wide nodes and append them, in the GPU layout,
// to a node array shared by the TLAS and every BLAS.
#pragma once
#include "bvh/binned_sah.h"
#include "kernels/layout.h"
#include <cstdint>
#include <vector>

namespace masq {

struct WideBvhInfo {
  std::int32_t root = -1;  // index in the node array
  std::size_t nodes = 0;
  std::size_t leaves = 0;
  double sah_cost = 0;     // traversal 1 per wide node visit, intersection 1 per reference
  int depth = 0;           // wide levels
  int stack_need = 0;      // worst-case traversal stack entries (kernel has MASQ_STACK_SIZE)
};

// Leaf references are appended to `refs` as ref_ids[order[i]] (e.g. primitive or
// instance ids). Throws masq::Error if traversal would need more than the kernel's
// fixed stack.
WideBvhInfo append_wide_bvh(const BinaryBvh& bvh, const std::vector<std::int32_t>& ref_ids,
                            std::vector<kernel::WideNode>& nodes, std::vector<std::int32_t>& refs);

} // namespace masq
