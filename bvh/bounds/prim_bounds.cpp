#include "bvh/bounds/prim_bounds.h"
#include "bvh/packed_scene.h"
#include "scenes/prim_table.h"
#include "masq/error.h"
#include <algorithm>
#include <cmath>
#include <string>

namespace masq {

double BallHull::support(const glm::dvec3& dir) const {
  double len = glm::length(dir);
  double best = -INFINITY;
  for (int i = 0; i < count; ++i) best = std::max(best, glm::dot(dir, centre[i]) + radius[i] * len);
  return best;
}

BallHull::Pair BallHull::support_pair(const glm::dvec3& dir) const {
  double len = glm::length(dir);
  Pair p{-INFINITY, -INFINITY};
  for (int i = 0; i < count; ++i) {
    const double d = glm::dot(dir, centre[i]);
    const double r = radius[i] * len;
    p.plus = std::max(p.plus, d + r);
    p.minus = std::max(p.minus, -d + r);
  }
  return p;
}

namespace {
BallHull hull_of(const PrimBalls& balls, int count) {
  BallHull h;
  for (int i = 0; i < count; ++i) {
    h.centre[std::size_t(i)] = glm::dvec3(balls[std::size_t(i)].centre);
    h.radius[std::size_t(i)] = balls[std::size_t(i)].radius;
  }
  h.count = count;
  return h;
}
} // namespace

BallHull ball_hull(const Geometry& g, std::size_t prim) {
  const ScenePrimRow& row = scene_prim_row(g.type);
  if (row.mesh) throw Error(std::string("bounds: ") + prim_type_name(g.type) + "s have no ball hull");
  PrimBalls balls;
  const int count = row.balls(g, prim, balls);
  return hull_of(balls, count);
}

BallHull ball_hull(const PackedScene& s, int geom, int prim) {
  const kernel::Geometry& g = s.geoms.at(std::size_t(geom));
  if (g.type < 0 || g.type >= MASQ_PRIM_TYPE_COUNT || scene_prim_row_of_kernel_type(g.type).mesh)
    throw Error("bounds: geometry " + std::to_string(geom) + " of type " + std::to_string(g.type) +
                " has no ball hull");
  return prim_hull(s, geom, prim);
}

BallHull prim_hull(const PackedScene& s, int geom, int prim) {
  const kernel::Geometry& g = s.geoms.at(std::size_t(geom));
  PrimBalls balls;
  const int count = scene_prim_row_of_kernel_type(g.type).kernel_balls(s, std::size_t(g.first + prim), balls);
  return hull_of(balls, count);
}

Aabb hull_box(const BallHull& h) {
  Aabb b;
  for (int i = 0; i < h.count; ++i) {
    b.grow(h.centre[i] - glm::dvec3(h.radius[i]));
    b.grow(h.centre[i] + glm::dvec3(h.radius[i]));
  }
  return b;
}

glm::dvec3 row_lengths(const Affine3& xf) {
  glm::dvec3 row_len;
  for (int k = 0; k < 3; ++k) row_len[k] = glm::length(glm::dvec3(xf.linear[0][k], xf.linear[1][k], xf.linear[2][k]));
  return row_len;
}

Aabb hull_world_box(const BallHull& h, const Affine3& xf) { return hull_world_box(h, xf, row_lengths(xf)); }

Aabb hull_world_box(const BallHull& h, const Affine3& xf, const glm::dvec3& row_len) {
  Aabb b;
  for (int i = 0; i < h.count; ++i) {
    glm::dvec3 c = xf.apply_point(h.centre[i]);
    b.grow(c - h.radius[i] * row_len);
    b.grow(c + h.radius[i] * row_len);
  }
  return b;
}

double hull_max_radius(const BallHull& h) {
  double r = 0;
  for (int i = 0; i < h.count; ++i) r = std::max(r, h.radius[i]);
  return r;
}

} // namespace masq
