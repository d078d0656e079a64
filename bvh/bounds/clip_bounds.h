// Conservative bounds of the part of one primitive that lies inside an axis-aligned
// slab {x : lo <= x[axis] <= hi}: the box SBVH's spatial splits give each piece of a
// split reference (bvh/binary/sbvh.h). Every returned box contains that part of the primitive
// (object space, double precision); an empty box means the primitive misses the slab.
//  capsule / round cone: the sub-segment whose swept balls can reach the slab, boxed and
//                        inflated by the larger end radius of the piece;
//  triangle:             the triangle polygon clipped exactly (Sutherland-Hodgman);
//  curve:                the sub-curve between the parameters where the control hull
//                        enters and leaves the widened slab (Bezier clipping, de
//                        Casteljau split), its control points boxed and inflated by r;
//  sphere:               its box intersected with the slab.
#pragma once
#include "bvh/bounds/aabb.h"
#include "scenes/scene.h"
#include <array>
#include <functional>

namespace masq {

Aabb clip_segment(const glm::dvec3& a, double ra, const glm::dvec3& b, double rb, int axis, double lo, double hi);
Aabb clip_triangle(const std::array<glm::dvec3, 3>& v, int axis, double lo, double hi);
Aabb clip_curve(const std::array<glm::dvec3, 4>& p, double radius, int axis, double lo, double hi);
Aabb clip_sphere(const glm::dvec3& centre, double radius, int axis, double lo, double hi);

// Clip primitive `prim` of geometry g (object space) to the slab.
Aabb clip_primitive(const Geometry& g, std::size_t prim, int axis, double lo, double hi);

// What SBVH asks of a primitive set: the bounds of item i (an index into the builder's
// box array) inside a slab.
using PrimClipper = std::function<Aabb(int item, int axis, double lo, double hi)>;

} // namespace masq
