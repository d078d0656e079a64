// Bounding balls in double precision: Welzl's exact minimum ball of a small point set,
// and the EPOS-26 fit of Larsson 2008 for balls of balls (the primitives' hulls): the
// exact minimum ball of the extremal points along 13 fixed directions, then grown until
// every input ball is covered.
#pragma once
#include "bvh/bounds/prim_bounds.h"
#include <glm/glm.hpp>
#include <span>
#include <vector>

namespace masq {

struct Ball {
  glm::dvec3 centre{0.0};
  double radius = -1.0; // < 0: empty
};

// Minimum enclosing ball of points (Welzl 1991, move-to-front). Intended for small sets
// (tens of points): recursion depth is the point count.
Ball min_ball(std::span<const glm::dvec3> points);

// Near-optimal ball containing every ball of every hull: EPOS-26 on the hulls' ball
// centres (extremes taken by support, so radii count), then Ritter-style growth over all
// balls. Containment holds in exact arithmetic; callers that store the ball in fp32
// recompute the radius about the rounded centre (bv_fit.cpp).
Ball epos26_ball(std::span<const BallHull> hulls);

} // namespace masq
