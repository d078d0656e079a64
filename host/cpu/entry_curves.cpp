#include "host/cpu/entry_curves.h"
#include "bvh/nodes/compact_instance.h"
#include "scenes/prim_table.h"
#include <algorithm>

namespace masq {

void entry_curves(const PackedScene& ps, HugePageVector<EntryCurve>& out) {
  out.assign(ps.curves.empty() ? 0 : ps.masq_instances.size(), EntryCurve{});
  if (ps.curves.empty()) return;
  for (std::size_t k = 0; k < ps.masq_instances.size(); ++k) {
    const kernel::MasqInstance& e = ps.masq_instances[k];
    // Entries that point outside the arrays keep a zero curve (radius 0: every call
    // misses); the kernels' own checks decide what such a structure means.
    const std::size_t owner = masq_owner(e);
    if (owner >= ps.masq_owners.size()) continue;
    const std::int32_t geom = ps.masq_owners[owner].geom;
    if (geom < 0 || std::size_t(geom) >= ps.geoms.size()) continue;
    const kernel::Geometry& g = ps.geoms[std::size_t(geom)];
    if (g.type != MASQ_CPU_ENTRY_COPY_TYPE) continue;
    const std::int64_t prim = std::int64_t(g.first) + e.prim;
    if (e.prim < 0 || prim >= std::int64_t(ps.curves.size())) continue;
    out[k].curve = ps.curves[std::size_t(prim)];
  }
}

bool entry_packets(const PackedScene& ps) {
  if (!ps.instances.empty() || ps.masq_instances.empty()) return false;
  return std::all_of(ps.geoms.begin(), ps.geoms.end(),
                     [](const kernel::Geometry& g) { return scene_prim_row_of_kernel_type(g.type).order_free; });
}

} // namespace masq
