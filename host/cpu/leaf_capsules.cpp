#include "host/cpu/leaf_capsules.h"
#include "bvh/nodes/wide_bvh.h"
#include "masq/error.h"
#include <limits>
#include <string>
#include <vector>

namespace masq {

namespace {

// Copies the capsules of every leaf under `root` (a BLAS of geometry g). The walk visits
// each node once and skips what points outside the arrays, so that a corrupt structure
// (a cycle, a stray index) reaches the kernels' step budget and fault report
// (host/trace_faults.h) rather than ending here.
void copy_leaves(const PackedScene& ps, std::int32_t root, const kernel::Geometry& g, std::vector<bool>& seen,
                 LeafCapsuleRows& out) {
  const std::size_t nodes = ps.node_count();
  std::vector<std::int32_t> todo{root};
  while (!todo.empty()) {
    const std::int32_t node = todo.back();
    todo.pop_back();
    if (node < 0 || std::size_t(node) >= nodes || seen[std::size_t(node)]) continue;
    seen[std::size_t(node)] = true;
    for (const NodeSlot& s : node_slots(ps, node)) {
      if (s.count < 0) continue;
      if (s.count == 0) {
        todo.push_back(s.child);
        continue;
      }
      for (std::int32_t j = 0; j < s.count; ++j) {
        const std::int64_t slot = std::int64_t(s.child) + j;
        if (slot < 0 || std::size_t(slot) >= ps.refs.size()) break;
        const std::int64_t prim = std::int64_t(g.first) + ps.refs[std::size_t(slot)];
        if (prim < 0 || std::size_t(prim) >= ps.capsules.size()) continue;
        const kernel::Capsule& c = ps.capsules[std::size_t(prim)];
        const float row[LeafCapsuleRows::kRows] = {c.a[0], c.a[1], c.a[2], c.b[0], c.b[1], c.b[2], c.radius};
        for (int k = 0; k < LeafCapsuleRows::kRows; ++k)
          out.rows[std::size_t(k) * std::size_t(out.stride) + std::size_t(slot)] = row[k];
      }
    }
  }
}

} // namespace

void leaf_capsules(const PackedScene& ps, LeafCapsuleRows& out) {
  out.stride = 0; // sized at the first BLAS of capsules: the references and four more
  std::vector<bool> seen(ps.node_count(), false); // nodes walked (instances of one geometry share a BLAS)
  for (const kernel::Instance& inst : ps.instances) {
    if (inst.blas_root < 0 || inst.geom < 0 || std::size_t(inst.geom) >= ps.geoms.size()) continue;
    const kernel::Geometry& g = ps.geoms[std::size_t(inst.geom)];
    if (g.type != MASQ_CPU_LEAF_COPY_TYPE) continue;
    // As long as the references and four more: every block of four a leaf starts is
    // then inside the copy. Leaves name their first reference by an int32.
    if (out.stride == 0) {
      if (ps.refs.size() > std::size_t(std::numeric_limits<std::int32_t>::max() - 8))
        throw Error("cpu: " + std::to_string(ps.refs.size()) +
                    " BLAS references are more than the cpu's leaf copy can index (int32)");
      out.stride = int((ps.refs.size() + 4 + 3) / 4 * 4);
      out.rows.assign(std::size_t(LeafCapsuleRows::kRows) * std::size_t(out.stride), 0.0f);
    }
    copy_leaves(ps, inst.blas_root, g, seen, out);
  }
  if (out.stride == 0) out.rows.clear();
}

} // namespace masq
