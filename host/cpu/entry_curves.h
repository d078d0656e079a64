// The cpu trace units' own copy of the curves that compact masquerade entries name, in
// entry order: slot k holds the curve of entry masq_instances[k] (zeros where an entry
// names another primitive type). The entries lie in the order the TLAS leaves name them
// (bvh/twolevel/entry_order.h), so a leaf's curves then lie side by side as its entries
// do, instead of wherever the scene's file put them: the curve record was the walk's
// most expensive load (perf on the bear's curve shadow rays, docs/results.md). The
// arithmetic is unchanged, so are the bits of every trace.
#pragma once
#include "bvh/packed_scene.h"
#include <vector>

namespace masq {

// One curve on a cache line of its own (a Curve is 64 bytes): the walk's prefetch of an
// entry's curve is then one line, not two.
struct alignas(64) EntryCurve {
  kernel::Curve curve;
};
static_assert(sizeof(EntryCurve) == sizeof(kernel::Curve), "entry curves are read as a Curve array");

// Fills `out` with the copy of ps (empty where ps has no curves), in the storage out
// already has where it holds the copy (std::vector::assign).
void entry_curves(const PackedScene& ps, HugePageVector<EntryCurve>& out);

// Whether camera rays may go in packets through ps's TLAS (KernelData::entry_packets,
// kernels/packet_walk_cpp.h): it holds compact masquerade entries alone (no Instance),
// of types whose robust intersectors take a crossing whatever order the entries are met
// in (ScenePrimRow::order_free: capsules and curves).
bool entry_packets(const PackedScene& ps);

} // namespace masq
