// The cpu trace units' own copy of the capsules of every BLAS leaf, in leaf order: slot i
// holds the capsule that leaf reference refs[i] names. A leaf's capsules then lie side
// by side, and the walk no longer waits for a reference before it can fetch the capsule
// it names; the reference is read only for a hit. Embree copies primitives into its
// leaves the same way. The copy is stored as seven rows (ax ay az bx by bz radius) of
// `stride` floats, so that four lanes of a coordinate are one load
// (kernels/capsule_simd_cpp.h's capsule_rows4); stride is the references' count plus at
// least four zero slots, so a block of four from any leaf stays inside its row. Empty
// for a scene with no capsule BLAS; slots outside capsule BLAS leaves (TLAS entries,
// other types) are left zero. The bits of every trace are unchanged: the same capsule,
// the same arithmetic.
#pragma once
#include "bvh/packed_scene.h"
#include <vector>

namespace masq {

struct LeafCapsuleRows {
  static constexpr int kRows = 7;
  HugePageVector<float> rows; // kRows x stride (scenes/huge_page_vector.h)
  int stride = 0;
};

// Fills `out` with the copy of ps, in the storage out already has where it holds the
// copy (std::vector::assign), so a backend that sets scene after scene keeps its pages.
void leaf_capsules(const PackedScene& ps, LeafCapsuleRows& out);

} // namespace masq
