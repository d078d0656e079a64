#include "host/cpu/leaf_capsules.h"
#include "bvh/nodes/wide_bvh.h"
#include <set>

namespace masq {

namespace {

// Every leaf slot under `node`, in walk order.
void leaf_slots(const PackedScene& ps, std::int32_t node, std::vector<std::int32_t>& out) {
  for (const NodeSlot& s : node_slots(ps, node)) {
    if (s.count < 0) continue;
    if (s.count == 0) {
      leaf_slots(ps, s.child, out);
      continue;
    }
    for (std::int32_t j = 0; j < s.count; ++j) out.push_back(s.child + j);
  }
}

} // namespace

std::vector<kernel::Capsule> leaf_capsules(const PackedScene& ps) {
  std::vector<kernel::Capsule> out;
  if (ps.capsules.empty()) return out;
  std::set<std::int32_t> done; // BLAS roots copied (instances of one geometry share theirs)
  std::vector<std::int32_t> slots;
  for (const kernel::Instance& inst : ps.instances) {
    if (inst.blas_root < 0 || !done.insert(inst.blas_root).second) continue;
    const kernel::Geometry& g = ps.geoms[std::size_t(inst.geom)];
    if (g.type != MASQ_PRIM_CAPSULE) continue;
    slots.clear();
    leaf_slots(ps, inst.blas_root, slots);
    for (std::int32_t slot : slots) {
      // Sized to the last capsule slot: the masquerade's TLAS references need none.
      if (std::size_t(slot) >= out.size()) out.resize(std::size_t(slot) + 1);
      out[std::size_t(slot)] = ps.capsules[std::size_t(g.first + ps.refs[std::size_t(slot)])];
    }
  }
  return out;
}

} // namespace masq
