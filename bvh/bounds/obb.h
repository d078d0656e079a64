// Oriented bounding boxes of primitives, as the fp32 world-to-unit-box maps that a
// masquerade instance stores.
#pragma once
#include "bvh/bounds/aabb.h"
#include "bvh/mat3x4f.h"
#include "bvh/options.h"
#include "bvh/bounds/prim_bounds.h"
#include "scenes/scene.h"
#include <optional>
#include <string>

namespace masq {

// An object-space box: centre + axes (orthonormal columns) * [-half, half].
struct ObbFrame {
  glm::dvec3 centre{0.0};
  glm::dmat3 axes{1.0};
  glm::dvec3 half{0.0};
  double area() const { return 8.0 * (half.x * half.y + half.y * half.z + half.z * half.x); }
};

// OBB of a non-triangle primitive in object space: analytic for capsules and round
// round cones (axis and perpendicular radii, both end balls covered), a cube for spheres,
// `curve_obb` for curves. Conservative for the hull of ball_hull().
ObbFrame primitive_obb(const Geometry& g, std::size_t prim, CurveObb curve_obb = CurveObb::Tight);
// The same from the primitive's ball hull h (ball_hull(g, prim)), for callers that hold it.
ObbFrame primitive_obb(const Geometry& g, const BallHull& h, CurveObb curve_obb = CurveObb::Tight);
// primitive_obb's axes alone (the same bits, either curve OBB mode), from the primitive's
// ball hull h (ball_hull(g, prim)), without the box fitted along them: the compact
// masquerade entries fit their own box along the quantised axes.
glm::dmat3 primitive_obb_axes(const Geometry& g, const BallHull& h);

struct MasqueradeBox {
  Mat3x4f world_to_unit; // fp32 as stored: maps the primitive into [-1,1]^3 (verified)
  Mat3x4f unit_to_world; // its inverse (for drivers that take object-to-world)
  Aabb world_box;        // world AABB of the primitive (for the TLAS)
  double obb_area = 0;   // surface area of the world-space OBB
  double aabb_area = 0;  // surface area of the primitive's exact world AABB
};

// The masquerade map of a primitive placed by `object_to_world`. The double-precision
// map is rounded to fp32 and then checked in double against the hull's exact extent
// (its support function) under the STORED matrix, shrinking until it provably maps
// inside the unit box. Throws masq::Error for a primitive without volume (radius 0).
MasqueradeBox masquerade_box(const Geometry& g, std::size_t prim, const Affine3& object_to_world,
                             CurveObb curve_obb = CurveObb::Tight);
MasqueradeBox capsule_masquerade_box(const CapsulePrim& c, const Affine3& object_to_world);

// The rest of a MasqueradeBox once its world-to-unit map is final (as stored, or as the
// kernel decodes a compact entry): the inverse, the TLAS box (the primitive's exact
// world box `exact` clipped by the unit box's world image) and both areas. nullopt when
// the box comes out empty or not finite.
std::optional<MasqueradeBox> complete_masquerade_box(const Affine3& world_to_unit, const Aabb& exact);

// World AABB of a capsule under an affine map (exact).
Aabb capsule_world_box(const CapsulePrim& c, const Affine3& object_to_world);

// Affine helpers.
Affine3 inverse(const Affine3& a);
Mat3x4f to_mat3x4f(const Affine3& a); // rounded to nearest
Affine3 from_mat3x4f(const Mat3x4f& m);

} // namespace masq
