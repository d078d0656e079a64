// Every non-triangle primitive is contained in the convex hull of at most four balls:
// capsule and round cone exactly (their two end balls), sphere exactly, and a cubic
// Bezier curve swept by a ball (its control points' balls: the curve lies in the
// control polygon's convex hull). Bounding boxes of any orientation follow from the
// hull's support function, so one routine serves AABBs, OBBs and their verification.
#pragma once
#include "bvh/bounds/aabb.h"
#include "scenes/scene.h"
#include <array>

namespace masq {

struct PackedScene;

struct BallHull {
  std::array<glm::dvec3, 4> centre{};
  std::array<double, 4> radius{};
  int count = 0;
  // max over the hull of dot(dir, x): the support function.
  double support(const glm::dvec3& dir) const;
  // support(dir) and support(-dir), the same bits as the two calls (negating dir negates
  // every product and sum exactly), with one length and one dot product per ball.
  struct Pair {
    double plus = 0;
    double minus = 0;
  };
  Pair support_pair(const glm::dvec3& dir) const;
};

// The hull of primitive `prim` of a non-triangle geometry (object space).
BallHull ball_hull(const Geometry& g, std::size_t prim);
// The same from the fp32 copy a PackedScene holds (what the kernels intersect).
BallHull ball_hull(const PackedScene& s, int geom, int prim);
// Any primitive of a PackedScene as a hull: a triangle is its three vertices (balls of
// radius 0), the others their ball_hull.
BallHull prim_hull(const PackedScene& s, int geom, int prim);

// Exact AABB of the hull in object space, and of its image under an affine map (the
// image of a ball is an ellipsoid with support r * |row_k(L)| on axis k).
Aabb hull_box(const BallHull& h);
Aabb hull_world_box(const BallHull& h, const Affine3& object_to_world);
// The same, given row_lengths(object_to_world): the lengths of its linear part's rows,
// found once for many hulls under one map.
Aabb hull_world_box(const BallHull& h, const Affine3& object_to_world, const glm::dvec3& row_len);
glm::dvec3 row_lengths(const Affine3& object_to_world);

// The largest radius in the hull (the primitive's thickness scale).
double hull_max_radius(const BallHull& h);

} // namespace masq
