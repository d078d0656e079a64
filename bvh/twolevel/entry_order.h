// The compact masquerade entries renumbered in the order the TLAS's leaf references name
// them (bvh/twolevel/build_accel.cpp). The entries are appended in primitive order, while
// a TLAS leaf holds primitives that lie side by side in space, often of different strands
// a whole strand apart; read through the leaves in that order, every entry a ray tests
// was a cache line of its own (measured: the entry's load was the traversal's costliest
// instruction on the bear's curve shadow rays). In leaf order a leaf's entries share
// lines and the leaves of one node lie together. Which entry a leaf names does not
// change, nor the order a ray tests them in, so every hit stays the same, bit for bit.
#pragma once
#include "bvh/packed_scene.h"
#include <cstddef>

namespace masq {

// Renumbers ps's compact masquerade entries in the order of their first reference in
// ps.refs[first_tlas_ref, end) (the TLAS's leaves, just appended), rewriting those
// references, masq_instances, their instance_object_to_world rows and tlas_leaf_order.
// Entries no leaf names (none, for a TLAS over every entry) keep their relative order
// after the named ones.
void order_compact_entries_by_leaves(PackedScene& ps, std::size_t first_tlas_ref);

} // namespace masq
