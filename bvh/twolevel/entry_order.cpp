#include "bvh/twolevel/entry_order.h"
#include "masq/error.h"
#include <algorithm>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace masq {

void order_compact_entries_by_leaves(PackedScene& ps, std::size_t first_tlas_ref) {
  const std::size_t n = ps.masq_instances.size();
  if (n == 0) return;
  if (first_tlas_ref > ps.refs.size() || ps.instance_object_to_world.size() != ps.tlas_entry_count())
    throw Error("accel: compact entries out of step with the TLAS");
  constexpr std::int32_t kUnnamed = -1;
  std::vector<std::int32_t> new_of(n, kUnnamed); // old compact index -> new
  std::int32_t next = 0;
  for (std::size_t r = first_tlas_ref; r < ps.refs.size(); ++r) {
    const std::int32_t ref = ps.refs[r];
    if (ref >= 0) continue; // an Instance
    const std::size_t old = std::size_t(~ref);
    if (old >= n) throw Error("accel: TLAS leaf names compact entry " + std::to_string(old) + " of " + std::to_string(n));
    if (new_of[old] == kUnnamed) new_of[old] = next++;
  }
  for (std::int32_t& k : new_of)
    if (k == kUnnamed) k = next++;
  for (std::size_t r = first_tlas_ref; r < ps.refs.size(); ++r)
    if (ps.refs[r] < 0) ps.refs[r] = ~new_of[std::size_t(~ps.refs[r])];

  const std::size_t base = ps.instances.size(); // compact entry e is TLAS entry base + e
  HugePageVector<kernel::MasqInstance> entries(n);
  HugePageVector<Mat3x4f> unit_to_world(n); // on recycled huge pages, as `entries` (no fresh faults a build)
  for (std::size_t old = 0; old < n; ++old) {
    entries[std::size_t(new_of[old])] = ps.masq_instances[old];
    unit_to_world[std::size_t(new_of[old])] = ps.instance_object_to_world[base + old];
  }
  ps.masq_instances = std::move(entries);
  std::copy(unit_to_world.begin(), unit_to_world.end(), ps.instance_object_to_world.begin() + std::ptrdiff_t(base));
  for (std::int32_t& e : ps.tlas_leaf_order)
    if (std::size_t(e) >= base) e = std::int32_t(base) + new_of[std::size_t(e) - base];
}

} // namespace masq
