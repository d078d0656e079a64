// Tight oriented boxes of sets of ball hulls, in double (a DiTO-style fit, Larsson &
// Kallberg 2011, plus PCA): candidate frames from the world axes, the principal axes
// of the ball centres, and the edges and normal of a large triangle spanned by
// extremal points; the candidate with the least surface area over ALL balls wins.
#pragma once
#include "bvh/bounds/obb.h"
#include "bvh/bounds/prim_bounds.h"
#include <span>

namespace masq {

// Extent of the hulls along a unit axis: [min, max] of dot(axis, x).
struct Interval {
  double lo = INFINITY;
  double hi = -INFINITY;
};
Interval hull_extent(std::span<const BallHull> hulls, const glm::dvec3& axis);

// Eigenvectors of a symmetric 3x3 matrix by cyclic Jacobi rotations (columns of the
// result; orthonormal to rounding).
glm::dmat3 symmetric_eigenvectors(glm::dmat3 a);

// The fitted box (axes: orthonormal columns). Empty input gives half = 0 at the origin.
ObbFrame fit_obb(std::span<const BallHull> hulls);

// The box of the hulls in a given orthonormal frame (axes as columns).
ObbFrame obb_in_frame(std::span<const BallHull> hulls, const glm::dmat3& axes);

} // namespace masq
