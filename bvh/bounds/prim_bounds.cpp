#include "bvh/bounds/prim_bounds.h"
#include "bvh/packed_scene.h"
#include "masq/error.h"
#include <algorithm>
#include <cmath>

namespace masq {

double BallHull::support(const glm::dvec3& dir) const {
  double len = glm::length(dir);
  double best = -INFINITY;
  for (int i = 0; i < count; ++i) best = std::max(best, glm::dot(dir, centre[i]) + radius[i] * len);
  return best;
}

namespace {
BallHull two(const glm::vec3& a, float ra, const glm::vec3& b, float rb) {
  BallHull h;
  h.centre[0] = glm::dvec3(a);
  h.radius[0] = ra;
  h.centre[1] = glm::dvec3(b);
  h.radius[1] = rb;
  h.count = 2;
  return h;
}
glm::vec3 v3(const float* p) { return {p[0], p[1], p[2]}; }
} // namespace

BallHull ball_hull(const Geometry& g, std::size_t prim) {
  switch (g.type) {
    case PrimType::Capsule: {
      const CapsulePrim& c = g.capsules.at(prim);
      return two(c.a, c.radius, c.b, c.radius);
    }
    case PrimType::RoundCone: {
      const RoundConePrim& c = g.round_cones.at(prim);
      return two(c.a, c.ra, c.b, c.rb);
    }
    case PrimType::Sphere: {
      const SpherePrim& s = g.spheres.at(prim);
      BallHull h;
      h.centre[0] = glm::dvec3(s.center);
      h.radius[0] = s.radius;
      h.count = 1;
      return h;
    }
    case PrimType::Curve: {
      const CurvePrim& c = g.curves.at(prim);
      BallHull h;
      for (int i = 0; i < 4; ++i) {
        h.centre[i] = glm::dvec3(c.p[i]);
        h.radius[i] = c.radius;
      }
      h.count = 4;
      return h;
    }
    case PrimType::Triangle: break;
  }
  throw Error("bounds: triangles have no ball hull");
}

BallHull ball_hull(const PackedScene& s, int geom, int prim) {
  const kernel::Geometry& g = s.geoms.at(std::size_t(geom));
  std::size_t i = std::size_t(g.first + prim);
  switch (g.type) {
    case MASQ_PRIM_CAPSULE: {
      const kernel::Capsule& c = s.capsules.at(i);
      return two(v3(c.a), c.radius, v3(c.b), c.radius);
    }
    case MASQ_PRIM_ROUND_CONE: {
      const kernel::RoundCone& c = s.round_cones.at(i);
      return two(v3(c.a), c.ra, v3(c.b), c.rb);
    }
    case MASQ_PRIM_SPHERE: {
      const kernel::Sphere& sp = s.spheres.at(i);
      BallHull h;
      h.centre[0] = glm::dvec3(v3(sp.center));
      h.radius[0] = sp.radius;
      h.count = 1;
      return h;
    }
    case MASQ_PRIM_CURVE: {
      const kernel::Curve& c = s.curves.at(i);
      BallHull h;
      const float* p[4] = {c.p0, c.p1, c.p2, c.p3};
      for (int k = 0; k < 4; ++k) {
        h.centre[k] = glm::dvec3(v3(p[k]));
        h.radius[k] = c.radius;
      }
      h.count = 4;
      return h;
    }
    default: break;
  }
  throw Error("bounds: geometry " + std::to_string(geom) + " of type " + std::to_string(g.type) +
              " has no ball hull");
}

BallHull prim_hull(const PackedScene& s, int geom, int prim) {
  const kernel::Geometry& g = s.geoms.at(std::size_t(geom));
  if (g.type != MASQ_PRIM_TRIANGLE) return ball_hull(s, geom, prim);
  const kernel::Triangle& t = s.triangles.at(std::size_t(g.first + prim));
  BallHull h;
  const float* v[3] = {t.v0, t.v1, t.v2};
  for (int k = 0; k < 3; ++k) h.centre[std::size_t(k)] = glm::dvec3(v3(v[k]));
  h.count = 3;
  return h;
}

Aabb hull_box(const BallHull& h) {
  Aabb b;
  for (int i = 0; i < h.count; ++i) {
    b.grow(h.centre[i] - glm::dvec3(h.radius[i]));
    b.grow(h.centre[i] + glm::dvec3(h.radius[i]));
  }
  return b;
}

Aabb hull_world_box(const BallHull& h, const Affine3& xf) {
  glm::dvec3 row_len;
  for (int k = 0; k < 3; ++k) row_len[k] = glm::length(glm::dvec3(xf.linear[0][k], xf.linear[1][k], xf.linear[2][k]));
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
