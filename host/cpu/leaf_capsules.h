// The cpu trace units' own copy of the capsules of every BLAS leaf, in leaf order: slot i
// holds the capsule that leaf reference refs[i] names (kernels/traverse.h reads it as
// KD(leaf_capsules)[first + j]). A leaf's capsules then lie side by side, and the walk
// no longer waits for a reference before it can fetch the capsule it names; the
// reference is read only for a hit. Embree copies primitives into its leaves the same
// way. The copy is as long as the references (empty for a scene with no capsule BLAS);
// slots outside capsule BLAS leaves (TLAS entries, other types) are left zero.
// The bits of every trace are unchanged: the same capsule, the same arithmetic.
#pragma once
#include "bvh/packed_scene.h"
#include <vector>

namespace masq {

std::vector<kernel::Capsule> leaf_capsules(const PackedScene& ps);

} // namespace masq
