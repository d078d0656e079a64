#include "bench/ray_sets.h"
#include "scenes/camera.h"
#include "scenes/error.h"
#include <cmath>
#include <numbers>
#include <random>

namespace masq {

const char* ray_set_name(RaySet s) {
  switch (s) {
    case RaySet::Primary: return "primary";
    case RaySet::Shadow: return "shadow";
    case RaySet::Diffuse: return "diffuse";
  }
  return "?";
}

RaySet parse_ray_set(const std::string& name) {
  for (RaySet s : {RaySet::Primary, RaySet::Shadow, RaySet::Diffuse})
    if (name == ray_set_name(s)) return s;
  throw Error("unknown ray set '" + name + "' (primary, shadow, diffuse)");
}

glm::dvec3 shadow_light(const Camera& camera) {
  glm::dvec3 back = camera.eye - camera.target;
  double dist = glm::length(back);
  glm::dvec3 w = back / dist;
  glm::dvec3 right = glm::normalize(glm::cross(camera.up, w));
  glm::dvec3 up = glm::cross(w, right);
  return camera.target + dist * glm::normalize(1.0 * up + 0.6 * right + 0.4 * w);
}

namespace {

glm::dvec3 hit_point(const kernel::Ray& r, const kernel::Hit& h) {
  return glm::dvec3(r.org[0], r.org[1], r.org[2]) + double(h.t) * glm::dvec3(r.dir[0], r.dir[1], r.dir[2]);
}

// Cosine-weighted direction about unit n (Malley's method on an orthonormal frame).
glm::dvec3 cosine_direction(const glm::dvec3& n, double u1, double u2) {
  glm::dvec3 a = std::abs(n.x) > 0.9 ? glm::dvec3(0, 1, 0) : glm::dvec3(1, 0, 0);
  glm::dvec3 t = glm::normalize(glm::cross(a, n));
  glm::dvec3 b = glm::cross(n, t);
  double rad = std::sqrt(u1), phi = 2.0 * std::numbers::pi * u2;
  return glm::normalize(rad * std::cos(phi) * t + rad * std::sin(phi) * b + std::sqrt(std::max(0.0, 1.0 - u1)) * n);
}

} // namespace

std::vector<kernel::Ray> make_secondary_rays(RaySet set, const Camera& camera, std::span<const kernel::Ray> primary,
                                             std::span<const kernel::Hit> hits, std::uint64_t seed) {
  if (primary.size() != hits.size()) throw Error("secondary rays: primary rays and hits differ in count");
  std::vector<kernel::Ray> out;
  if (set == RaySet::Primary) return {primary.begin(), primary.end()};
  const glm::dvec3 light = shadow_light(camera);
  for (std::size_t i = 0; i < primary.size(); ++i) {
    const kernel::Hit& h = hits[i];
    if (h.prim < 0) continue;
    glm::dvec3 p = hit_point(primary[i], h);
    if (set == RaySet::Shadow) {
      out.push_back(make_ray(p, light - p, 0.0f, 1.0f));
      continue;
    }
    glm::dvec3 n(h.normal[0], h.normal[1], h.normal[2]);
    glm::dvec3 d(primary[i].dir[0], primary[i].dir[1], primary[i].dir[2]);
    if (!(glm::length(n) > 0)) continue; // degenerate normal: no bounce
    n = glm::normalize(n);
    if (glm::dot(n, d) > 0) n = -n;
    std::mt19937_64 rng(seed * 0x9E3779B97F4A7C15ull + i);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    double u1 = u(rng), u2 = u(rng);
    out.push_back(make_ray(p, cosine_direction(n, u1, u2)));
  }
  return out;
}

} // namespace masq
