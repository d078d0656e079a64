#include "scenes/scene.h"
#include "scenes/error.h"
#include <cmath>
#include <string>

namespace masq {

const char* prim_type_name(PrimType t) {
  switch (t) {
    case PrimType::Triangle: return "triangle";
    case PrimType::Capsule: return "capsule";
  }
  return "?";
}

std::size_t Scene::primitive_count() const {
  std::size_t n = 0;
  for (const Instance& inst : instances) n += geometries[inst.geometry].primitive_count();
  return n;
}

namespace {
bool finite3(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

std::string where(std::size_t g, const char* what, std::size_t i) {
  return "geometry " + std::to_string(g) + " " + what + " " + std::to_string(i);
}

void validate_geometry(const Geometry& geo, std::size_t g) {
  if (geo.type == PrimType::Triangle) {
    if (!geo.capsules.empty()) throw Error("scene: " + where(g, "(triangles) holds capsules", 0));
    for (std::size_t i = 0; i < geo.vertices.size(); ++i)
      if (!finite3(geo.vertices[i])) throw Error("scene: " + where(g, "vertex", i) + " is not finite");
    for (std::size_t i = 0; i < geo.triangles.size(); ++i) {
      const glm::uvec3& t = geo.triangles[i];
      if (t.x >= geo.vertices.size() || t.y >= geo.vertices.size() || t.z >= geo.vertices.size())
        throw Error("scene: " + where(g, "triangle", i) + " indexes a vertex beyond " +
                    std::to_string(geo.vertices.size()));
    }
  } else {
    if (!geo.triangles.empty()) throw Error("scene: " + where(g, "(capsules) holds triangles", 0));
    for (std::size_t i = 0; i < geo.capsules.size(); ++i) {
      const CapsulePrim& c = geo.capsules[i];
      if (!finite3(c.a) || !finite3(c.b)) throw Error("scene: " + where(g, "capsule", i) + " has a non-finite endpoint");
      if (!std::isfinite(c.radius) || c.radius < 0.0f)
        throw Error("scene: " + where(g, "capsule", i) + " has radius " + std::to_string(c.radius) +
                    " (must be finite and >= 0)");
    }
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
