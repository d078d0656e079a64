#include "scenes/scene.h"
#include "scenes/prim_table.h"
#include "masq/error.h"
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

namespace masq {

std::size_t Scene::primitive_count() const {
  std::size_t n = 0;
  // Callable before validate_scene (found by ASan: EmbreePeer::set_scene counted first):
  // an instance of a geometry that does not exist counts nothing; validation names it.
  for (const Instance& inst : instances)
    if (inst.geometry < geometries.size()) n += geometries[inst.geometry].primitive_count();
  return n;
}

std::size_t Geometry::primitive_count() const {
  // Like Scene::primitive_count, callable before validation: a type no row holds counts nothing.
  return static_cast<std::size_t>(type) < prim_type_count ? scene_prim_row(type).count(*this) : 0;
}

namespace {
// A geometry holds primitives of its own type only.
void check_only_own_type(const Geometry& geo, std::size_t g) {
  for (std::size_t i = 0; i < prim_type_count; ++i) {
    const auto type = static_cast<PrimType>(i);
    if (type != geo.type && scene_prim_row(type).holds_any(geo))
      throw Error("scene: geometry " + std::to_string(g) + " (" + prim_type_name(geo.type) + "s) also holds " +
                  prim_type_name(type) + "s");
  }
}

void validate_geometry(const Geometry& geo, std::size_t g) {
  check_only_own_type(geo, g);
  scene_prim_row(geo.type).validate(geo, g);
}

// How far a geometry's primitives reach in object space: the largest |coordinate| of a
// hull ball's centre, and the largest radius.
struct Reach {
  double coordinate = 0.0;
  double radius = 0.0;
};
Reach reach_of(const Geometry& geo) {
  const ScenePrimRow& row = scene_prim_row(geo.type);
  Reach r;
  PrimBalls balls;
  for (std::size_t i = 0, n = row.count(geo); i < n; ++i) {
    const int k = row.balls(geo, i, balls);
    for (int j = 0; j < k; ++j) {
      const PrimBall& b = balls[std::size_t(j)];
      r.coordinate = std::max({r.coordinate, std::abs(double(b.centre.x)), std::abs(double(b.centre.y)),
                               std::abs(double(b.centre.z))});
      r.radius = std::max(r.radius, double(b.radius));
    }
  }
  return r;
}

std::string reach_error(const std::string& what, double reach) {
  auto g = [](double v) {
    char text[32];
    std::snprintf(text, sizeof text, "%.3g", v);
    return std::string(text);
  };
  return "scene: " + what + " reaches " + g(reach) + " from the origin; fp32 traversal needs " +
         "|coordinate| + radius <= 2^60 (" + g(kMaxSceneReach) +
         ") so that squared distances across the scene stay finite in fp32 (docs/robustness.md, \"Scene range\")";
}
} // namespace

void validate_scene(const Scene& scene) {
  if (scene.instances.empty()) throw Error("scene '" + scene.name + "': no instances (empty scene)");
  std::vector<Reach> reach(scene.geometries.size());
  for (std::size_t g = 0; g < scene.geometries.size(); ++g) {
    validate_geometry(scene.geometries[g], g);
    // Object space: where the intersectors run once a ray is transformed into it.
    reach[g] = reach_of(scene.geometries[g]);
    if (reach[g].coordinate + reach[g].radius > kMaxSceneReach)
      throw Error(reach_error("geometry " + std::to_string(g), reach[g].coordinate + reach[g].radius));
  }
  for (std::size_t i = 0; i < scene.instances.size(); ++i) {
    const Instance& inst = scene.instances[i];
    const std::string at = "scene: instance " + std::to_string(i);
    if (inst.geometry >= scene.geometries.size())
      throw Error(at + " names geometry " + std::to_string(inst.geometry) + " of " +
                  std::to_string(scene.geometries.size()));
    const glm::dmat3& m = inst.object_to_world.linear;
    for (int c = 0; c < 3; ++c)
      for (int r = 0; r < 3; ++r)
        if (!std::isfinite(m[c][r])) throw Error(at + " has a non-finite transform");
    for (int k = 0; k < 3; ++k)
      if (!std::isfinite(inst.object_to_world.translation[k])) throw Error(at + " has a non-finite translation");
    // Singular (or numerically singular) transforms cannot be inverted for the ray
    // transform: compare |det| with the product of column lengths.
    double scale = glm::length(m[0]) * glm::length(m[1]) * glm::length(m[2]);
    double det = glm::determinant(m);
    if (!(scale > 0.0) || std::abs(det) <= 1e-12 * scale)
      throw Error(at + " has a singular transform (det " + std::to_string(det) + ")");
    // World space: a bound on |coordinate| of the transformed primitives (a row's
    // absolute sum bounds the coordinate's growth, the Frobenius norm the radius's).
    const Reach& r = reach[inst.geometry];
    double world = r.coordinate + r.radius;
    if (!inst.object_to_world.is_identity()) {
      double rows = 0.0, frobenius = 0.0, shift = 0.0;
      for (int k = 0; k < 3; ++k) {
        rows = std::max(rows, std::abs(m[0][k]) + std::abs(m[1][k]) + std::abs(m[2][k]));
        frobenius += glm::dot(m[k], m[k]);
        shift = std::max(shift, std::abs(inst.object_to_world.translation[k]));
      }
      world = rows * r.coordinate + std::sqrt(frobenius) * r.radius + shift;
    }
    if (world > kMaxSceneReach) throw Error(reach_error("instance " + std::to_string(i), world));
  }
}

} // namespace masq
