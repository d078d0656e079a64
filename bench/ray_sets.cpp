#include "bench/ray_sets.h"
#include "scenes/camera.h"
#include "scenes/prim_table.h"
#include "masq/error.h"
#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>

namespace masq {

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

// World-space radius of the hit primitive (0 for triangles and for hits the scene does
// not know): the primitive's radius times the instance's largest axis scale.
double hit_radius(const Scene& scene, const kernel::Hit& h) {
  if (h.geom < 0 || std::size_t(h.geom) >= scene.geometries.size() || h.prim < 0) return 0.0;
  const Geometry& g = scene.geometries[h.geom];
  const std::size_t p = std::size_t(h.prim);
  if (p >= g.primitive_count()) return 0.0;
  const double r = prim_max_radius(g, p);
  double scale = 1.0;
  if (h.inst >= 0 && std::size_t(h.inst) < scene.instances.size()) {
    const glm::dmat3& m = scene.instances[h.inst].object_to_world.linear;
    scale = std::max({glm::length(m[0]), glm::length(m[1]), glm::length(m[2])});
  }
  return r * scale;
}

} // namespace

float spawn_tmin(const Scene& scene, const kernel::Hit& hit, const glm::dvec3& p, const glm::dvec3& d) {
  double len = glm::length(d);
  if (!(len > 0)) return 0.0f;
  double max_abs = std::max({std::abs(p.x), std::abs(p.y), std::abs(p.z)});
  // r/16: masq's robust intersectors need none (their self-intersection window is
  // 2^-10 r), but Embree 3's round curves report their own surface up to ~3% of r from
  // an origin on it (measured on the default bundle's shadow rays), and a peer
  // comparison must ask every tracer the same question. It is still far below the
  // primitive's features (a ray that re-crosses its own primitive does so ~2r away
  // unless it grazes). 2^-17 |p| (about 64 ulp of the coordinates) serves triangles.
  double eps = std::max(hit_radius(scene, hit) * 0x1p-4, max_abs * 0x1p-17);
  return float(eps / len);
}

std::vector<kernel::Ray> make_secondary_rays(RaySet set, const Scene& scene, std::span<const kernel::Ray> primary,
                                             std::span<const kernel::Hit> hits, std::uint64_t seed) {
  const Camera& camera = scene.camera;
  if (primary.size() != hits.size()) throw Error("secondary rays: primary rays and hits differ in count");
  std::vector<kernel::Ray> out;
  if (set == RaySet::Primary) return {primary.begin(), primary.end()};
  const glm::dvec3 light = shadow_light(camera);
  for (std::size_t i = 0; i < primary.size(); ++i) {
    const kernel::Hit& h = hits[i];
    if (h.prim < 0) continue;
    glm::dvec3 p = hit_point(primary[i], h);
    if (set == RaySet::Shadow) {
      out.push_back(make_ray(p, light - p, spawn_tmin(scene, h, p, light - p), 1.0f));
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
    glm::dvec3 dir = cosine_direction(n, u1, u2);
    out.push_back(make_ray(p, dir, spawn_tmin(scene, h, p, dir)));
  }
  return out;
}

} // namespace masq
