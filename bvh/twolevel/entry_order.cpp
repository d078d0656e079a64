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
  // The entries and their transforms moved to their new places in place, cycle by cycle
  // of the permutation. Copies of both arrays were new memory at every build: on
  // malloc's pages faulted in afresh (Ratboy's masquerade), or, moved onto kept huge
  // mappings (scenes/huge_page_vector.h), taking the mappings other arrays reuse (the
  // bear's masquerade build 97-99 -> 117-120 ms, in the kernel's page zeroing).
  Mat3x4f* unit_to_world = ps.instance_object_to_world.data() + base;
  std::vector<bool> placed(n, false);
  for (std::size_t start = 0; start < n; ++start) {
    if (placed[start]) continue;
    kernel::MasqInstance entry = ps.masq_instances[start];
    Mat3x4f transform = unit_to_world[start];
    for (std::size_t at = start; !placed[at];) {
      placed[at] = true;
      const std::size_t to = std::size_t(new_of[at]);
      std::swap(entry, ps.masq_instances[to]);
      std::swap(transform, unit_to_world[to]);
      at = to;
    }
  }
  for (std::int32_t& e : ps.tlas_leaf_order)
    if (std::size_t(e) >= base) e = std::int32_t(base) + new_of[std::size_t(e) - base];
}

} // namespace masq
