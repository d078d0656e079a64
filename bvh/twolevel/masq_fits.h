// The masquerade fits of a run of one geometry's primitives (bvh/twolevel/build_accel.cpp),
// computed on the build's threads (bvh/binary/parallel.h), each into its own slot, so the
// TLAS entries can then be appended in the serial order whatever the thread count.
#pragma once
#include "bvh/bounds/obb.h"
#include "bvh/nodes/compact_instance.h"
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

namespace masq {

struct MasqFit {
  std::optional<CompactMasquerade> compact; // when asked for and the map compacts
  MasqueradeBox full;                       // the 64-byte Instance's fit, when compact is empty
};

// fits[i] for prims[i] of g under object_to_world (fits.size() == prims.size()): the
// compact entry when try_compact and compact_masquerade gives one, else masquerade_box's
// fit. The caller's buffer is reused block after block: a fresh one per block was as
// much of the build as the fits' own arithmetic (zeroing and faulting 6 MiB a block).
void fit_masquerades(const Geometry& g, std::span<const std::int32_t> prims, const Affine3& object_to_world,
                     CurveObb curve_obb, bool try_compact, std::span<MasqFit> fits);

} // namespace masq
