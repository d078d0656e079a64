// Compact masquerade entries (kernels/layout.h, MasqInstance; docs/kernels.md, "Compact
// masquerade instances"): a primitive's world -> unit-box map as a quaternion, three
// bfloat16 scales and an fp32 translation, 32 bytes instead of the 64 of an Instance.
#pragma once
#include "bvh/bounds/obb.h"
#include "bvh/packed_scene.h"
#include "kernels/layout.h"
#include <cstdint>
#include <optional>
#include <span>

namespace masq {

// Bound on the kernel's decode error per matrix entry, relative to the entry (see
// compact_instance.cpp for why 8 u).
inline constexpr double kMasqDecodeRelError = 8.0 * 0x1p-24;

struct CompactMasquerade {
  kernel::MasqInstance inst; // owner bits 0: set_masq_owner
  // world_to_unit: the decoded map rounded to fp32 (what the kernel computes, within
  // its decode error); unit_to_world: the inverse of the exactly decoded map, rounded to
  // fp32 (the rayquery backend's driver instance); world_box and areas as for the
  // 64-byte form.
  MasqueradeBox box;
};

// The compact entry of a primitive placed by `object_to_world`, proved conservative:
// under the decoded map, and under every matrix within the kernel's decode error of
// it, the primitive's hull lies inside [-1,1]^3. nullopt where the form cannot hold it
// (a scale outside bfloat16's normal range, or no fit after shrinking); the caller then
// uses a 64-byte Instance. Throws masq::Error for a primitive without volume, as
// masquerade_box does. It takes no curve OBB mode: both give a curve the same axes
// (primitive_obb_axes), so the same entry.
std::optional<CompactMasquerade> compact_masquerade(const Geometry& g, std::size_t prim,
                                                    const Affine3& object_to_world);
// compact_masquerade of up to kCompactLanes primitives at once, the same entries: *out[i]
// gets prims[i]'s. Their fits run stage by stage, so that the primitives' chains of
// square roots and divisions overlap.
inline constexpr int kCompactLanes = 4;
void compact_masquerades(const Geometry& g, std::span<const std::int32_t> prims, const Affine3& object_to_world,
                         std::optional<CompactMasquerade>* const* out);

// The map the kernel decodes, in exact arithmetic: M_ij = sigma_i * N_ji (an integer
// of at most 31 bits times an 8-bit significand: exact in double) and t.
Affine3 decode_masq_instance(const kernel::MasqInstance& c);

// The owner index in the low 16 bits of s2_owner (owner < MASQ_MAX_OWNERS), written and read.
void set_masq_owner(kernel::MasqInstance& c, std::uint32_t owner);
std::uint32_t masq_owner(const kernel::MasqInstance& c);

// TLAS entry `entry` of s (Instances, then compact entries; PackedScene::tlas_entry) as a
// full Instance record: a compact entry with its decoded map rounded to fp32, geometry
// and scene instance from its owner. What the rayquery backend uploads and the host
// walks read. Throws masq::Error for an entry out of range.
kernel::Instance tlas_entry_instance(const PackedScene& s, std::size_t entry);

} // namespace masq
