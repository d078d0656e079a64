// Spatial-split BVH (Stich, Friedrich & Dietrich 2009, "Spatial Splits in Bounding
// Volume Hierarchies"): at each node the best binned object split (as
// build_binned_sah) competes with the best spatial split, whose plane cuts the
// references that straddle it into two clipped pieces (bvh/bounds/clip_bounds.h). Spatial
// splits are only tried where the object split's children overlap by more than
// alpha * (root area), and only while the reference count stays within the budget.
// The result is a BinaryBvh whose `order` may name a primitive several times (once per
// piece); leaf boxes bound the pieces, so the union of a primitive's leaves contains it.
#pragma once
#include "bvh/binary/binned_sah.h"
#include "bvh/bounds/clip_bounds.h"

namespace masq {

struct SbvhOptions {
  double alpha = 1e-5;      // overlap / root area above which spatial splits are tried
  double max_refs = 2.0;    // reference budget: at most max_refs x the primitive count (>= 1)
  int max_spatial_depth = 32; // no spatial split below this depth (the kernels' traversal stack is fixed)
};

struct SbvhStats {
  std::size_t references = 0;   // leaf references (primitives counted once per piece)
  std::size_t spatial_splits = 0;
  std::size_t object_splits = 0;
};

// boxes[i] is the AABB of item i; clip(i, axis, lo, hi) bounds its part inside a slab
// and must be conservative. Throws masq::Error on a bad box or option.
BinaryBvh build_sbvh(std::span<const Aabb> boxes, const PrimClipper& clip, const SahOptions& sah = {},
                     const SbvhOptions& opt = {}, SbvhStats* stats = nullptr);

} // namespace masq
