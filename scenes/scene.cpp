#include "scenes/scene.h"
#include "masq/error.h"
#include <cmath>
#include <string>
#include <utility>

namespace masq {

std::size_t Scene::primitive_count() const {
  std::size_t n = 0;
  // Callable before validate_scene (found by ASan: EmbreePeer::set_scene counted first):
  // an instance of a geometry that does not exist counts nothing; validation names it.
  for (const Instance& inst : instances)
    if (inst.geometry < geometries.size()) n += geometries[inst.geometry].primitive_count();
  return n;
}

namespace {
bool finite3(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

std::string where(std::size_t g, const char* what, std::size_t i) {
  return "geometry " + std::to_string(g) + " " + what + " " + std::to_string(i);
}

void check_radius(float r, std::size_t g, const char* what, std::size_t i) {
  if (!std::isfinite(r) || r < 0.0f)
    throw Error("scene: " + where(g, what, i) + " has radius " + std::to_string(r) + " (must be finite and >= 0)");
}

void check_point(const glm::vec3& p, std::size_t g, const char* what, std::size_t i) {
  if (!finite3(p)) throw Error("scene: " + where(g, what, i) + " has a non-finite point");
}

// A geometry holds primitives of its own type only.
void check_only_own_type(const Geometry& geo, std::size_t g) {
  const std::pair<PrimType, bool> holds[] = {{PrimType::Triangle, !geo.triangles.empty()},
                                             {PrimType::Capsule, !geo.capsules.empty()},
                                             {PrimType::RoundCone, !geo.round_cones.empty()},
                                             {PrimType::Sphere, !geo.spheres.empty()},
                                             {PrimType::Curve, !geo.curves.empty()}};
  for (auto [type, present] : holds)
    if (present && type != geo.type)
      throw Error("scene: geometry " + std::to_string(g) + " (" + prim_type_name(geo.type) + "s) also holds " +
                  prim_type_name(type) + "s");
}

void validate_geometry(const Geometry& geo, std::size_t g) {
  check_only_own_type(geo, g);
  switch (geo.type) {
    case PrimType::Triangle:
      for (std::size_t i = 0; i < geo.vertices.size(); ++i)
        if (!finite3(geo.vertices[i])) throw Error("scene: " + where(g, "vertex", i) + " is not finite");
      for (std::size_t i = 0; i < geo.triangles.size(); ++i) {
        const glm::uvec3& t = geo.triangles[i];
        if (t.x >= geo.vertices.size() || t.y >= geo.vertices.size() || t.z >= geo.vertices.size())
          throw Error("scene: " + where(g, "triangle", i) + " indexes a vertex beyond " +
                      std::to_string(geo.vertices.size()));
      }
      break;
    case PrimType::Capsule:
      for (std::size_t i = 0; i < geo.capsules.size(); ++i) {
        const CapsulePrim& c = geo.capsules[i];
        if (!finite3(c.a) || !finite3(c.b)) throw Error("scene: " + where(g, "capsule", i) + " has a non-finite endpoint");
        check_radius(c.radius, g, "capsule", i);
      }
      break;
    case PrimType::RoundCone:
      for (std::size_t i = 0; i < geo.round_cones.size(); ++i) {
        const RoundConePrim& c = geo.round_cones[i];
        check_point(c.a, g, "round cone", i);
        check_point(c.b, g, "round cone", i);
        check_radius(c.ra, g, "round cone", i);
        check_radius(c.rb, g, "round cone", i);
      }
      break;
    case PrimType::Sphere:
      for (std::size_t i = 0; i < geo.spheres.size(); ++i) {
        check_point(geo.spheres[i].center, g, "sphere", i);
        check_radius(geo.spheres[i].radius, g, "sphere", i);
      }
      break;
    case PrimType::Curve:
      for (std::size_t i = 0; i < geo.curves.size(); ++i) {
        for (const glm::vec3& p : geo.curves[i].p) check_point(p, g, "curve", i);
        check_radius(geo.curves[i].radius, g, "curve", i);
      }
      break;
  }
}
} // namespace

void validate_scene(const Scene& scene) {
  if (scene.instances.empty()) throw Error("scene '" + scene.name + "': no instances (empty scene)");
  for (std::size_t g = 0; g < scene.geometries.size(); ++g) validate_geometry(scene.geometries[g], g);
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
  }
}

} // namespace masq
