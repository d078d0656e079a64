// Oriented bounding boxes of primitives, as the fp32 world-to-unit-box maps that a
// masquerade instance stores.
#pragma once
#include "bvh/aabb.h"
#include "bvh/packed_scene.h"
#include "scenes/scene.h"

namespace masq {

struct MasqueradeBox {
  Mat3x4f world_to_unit; // fp32 as stored: maps the primitive into [-1,1]^3 (verified)
  Mat3x4f unit_to_world; // its inverse (for drivers that take object-to-world)
  Aabb world_box;        // world AABB of the primitive (for the TLAS)
  double obb_area = 0;   // surface area of the world-space OBB
};

// Analytic OBB of a capsule: the axis and two perpendicular radii, covering both caps,
// placed by `object_to_world`. The double-precision map is rounded to fp32 and then
// checked in double against the primitive's exact extent (support function of the
// swept ball) under the STORED matrix, shrinking until it provably maps inside the unit
// box. Throws masq::Error for a zero-radius capsule (it has no volume to box).
MasqueradeBox capsule_masquerade_box(const CapsulePrim& c, const Affine3& object_to_world);

// World AABB of a capsule under an affine map (exact: endpoints plus the ellipsoid's
// support r*|row_k(L)| on each axis).
Aabb capsule_world_box(const CapsulePrim& c, const Affine3& object_to_world);

// Affine helpers.
Affine3 inverse(const Affine3& a);
Mat3x4f to_mat3x4f(const Affine3& a); // rounded to nearest
Affine3 from_mat3x4f(const Mat3x4f& m);

} // namespace masq
