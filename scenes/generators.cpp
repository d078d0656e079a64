#include "scenes/generators.h"
#include "masq/error.h"
#include "scenes/prim_table.h"
#include <cmath>
#include <random>

namespace masq {

Geometry make_bundle(const BundleParams& p) {
  if (p.count <= 0 || !(p.radius > 0.0f))
    throw Error("bundle: count and radius must be positive (count " + std::to_string(p.count) + ", radius " +
                std::to_string(p.radius) + ")");
  const ScenePrimRow& row = scene_prim_row(p.prim);
  if (!row.add_bundle_strand) throw Error(std::string("bundle: strands cannot be ") + row.singular + "s");
  Geometry g;
  g.type = p.prim;
  std::mt19937_64 rng(p.seed);
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  const double tilt = glm::radians(p.tilt_deg);
  const glm::dvec3 axis(std::sin(tilt), std::cos(tilt), 0.0);
  // Two directions spanning the disc perpendicular to the axis.
  const glm::dvec3 e1(std::cos(tilt), -std::sin(tilt), 0.0);
  const glm::dvec3 e2(0.0, 0.0, 1.0);
  const double disc = 0.5 - p.radius;
  for (int i = 0; i < p.count; ++i) {
    double rr = p.count == 1 ? 0.0 : disc * std::sqrt(uni(rng));
    double phi = 2.0 * M_PI * uni(rng);
    glm::dvec3 c = rr * (std::cos(phi) * e1 + std::sin(phi) * e2);
    // Length 1 including the caps: the segment is 1 - 2r long.
    double half = 0.5 - p.radius;
    glm::dvec3 a = c - half * axis, b = c + half * axis;
    row.add_bundle_strand(g, a, b, 0.05 * e1, p.radius);
  }
  return g;
}

Geometry make_ground_plane(double height, double half_size) {
  Geometry g;
  g.type = PrimType::Triangle;
  float h = float(height), s = float(half_size);
  g.vertices = {{-s, h, -s}, {s, h, -s}, {s, h, s}, {-s, h, s}};
  g.triangles = {{0, 2, 1}, {0, 3, 2}}; // normal +Y
  return g;
}

Scene make_default_scene(const BundleParams& p) {
  Scene s;
  s.name = "bundle";
  s.geometries.push_back(make_bundle(p));
  s.geometries.push_back(make_ground_plane(-0.75, 3.0));
  s.instances.push_back({0, {}});
  s.instances.push_back({1, {}});
  s.camera.eye = {0.0, 0.45, -2.9};
  s.camera.target = {0.0, -0.1, 0.0};
  s.camera.fov_y_deg = 40.0;
  return s;
}

Geometry make_random_capsules(int count, float min_radius, float max_radius, double extent, std::uint64_t seed) {
  Geometry g;
  g.type = PrimType::Capsule;
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> pos(-extent, extent);
  std::uniform_real_distribution<double> len(0.0, 0.5 * extent);
  std::uniform_real_distribution<double> rad(min_radius, max_radius);
  std::normal_distribution<double> gauss;
  for (int i = 0; i < count; ++i) {
    glm::dvec3 a(pos(rng), pos(rng), pos(rng));
    glm::dvec3 dir(gauss(rng), gauss(rng), gauss(rng));
    glm::dvec3 b = a + len(rng) * glm::normalize(dir);
    g.capsules.push_back({glm::vec3(a), glm::vec3(b), float(rad(rng))});
  }
  return g;
}

Geometry make_random_cones(int count, float min_radius, float max_radius, double extent, std::uint64_t seed) {
  Geometry g;
  g.type = PrimType::RoundCone;
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> pos(-extent, extent);
  std::uniform_real_distribution<double> len(0.0, 0.5 * extent);
  std::uniform_real_distribution<double> rad(min_radius, max_radius);
  std::normal_distribution<double> gauss;
  for (int i = 0; i < count; ++i) {
    glm::dvec3 a(pos(rng), pos(rng), pos(rng));
    glm::dvec3 dir = glm::normalize(glm::dvec3(gauss(rng), gauss(rng), gauss(rng)));
    double ra = rad(rng), rb = rad(rng);
    // Every 8th: the b ball lies inside the a ball.
    double l = i % 8 == 7 ? 0.5 * ra : len(rng);
    if (i % 8 == 7) rb = 0.4 * ra;
    g.round_cones.push_back({glm::vec3(a), float(ra), glm::vec3(a + l * dir), float(rb)});
  }
  return g;
}

Geometry make_random_spheres(int count, float min_radius, float max_radius, double extent, std::uint64_t seed) {
  Geometry g;
  g.type = PrimType::Sphere;
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> pos(-extent, extent);
  std::uniform_real_distribution<double> rad(min_radius, max_radius);
  for (int i = 0; i < count; ++i) g.spheres.push_back({glm::vec3(pos(rng), pos(rng), pos(rng)), float(rad(rng))});
  return g;
}

Geometry make_random_curves(int count, float min_radius, float max_radius, double extent, std::uint64_t seed) {
  Geometry g;
  g.type = PrimType::Curve;
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> pos(-extent, extent);
  std::uniform_real_distribution<double> len(0.05 * extent, 0.5 * extent);
  std::uniform_real_distribution<double> rad(min_radius, max_radius);
  std::normal_distribution<double> gauss;
  for (int i = 0; i < count; ++i) {
    glm::dvec3 a(pos(rng), pos(rng), pos(rng));
    glm::dvec3 dir = glm::normalize(glm::dvec3(gauss(rng), gauss(rng), gauss(rng)));
    double radius = rad(rng);
    // Hair-like: at least 20 radii long (the phantom tube assumes a radius of
    // curvature well above r).
    double l = std::max(len(rng), 20.0 * radius);
    glm::dvec3 bend = glm::dvec3(gauss(rng), gauss(rng), gauss(rng)) * (0.15 * l);
    CurvePrim c{};
    for (int k = 0; k < 4; ++k) {
      double s = k / 3.0;
      glm::dvec3 p = a + (s * l) * dir + (k == 1 || k == 2 ? 1.0 : 0.0) * bend * (k == 1 ? 1.0 : -0.5);
      c.p[std::size_t(k)] = glm::vec3(p);
    }
    c.radius = float(radius);
    g.curves.push_back(c);
  }
  return g;
}

Geometry make_random_geometry(PrimType type, int count, float min_radius, float max_radius, double extent,
                              std::uint64_t seed) {
  return scene_prim_row(type).random(count, min_radius, max_radius, extent, seed);
}

Geometry make_random_mesh(int triangles, double extent, std::uint64_t seed) {
  Geometry g;
  g.type = PrimType::Triangle;
  int n = std::max(1, int(std::sqrt(triangles / 2.0)));
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> bump(-0.2 * extent, 0.2 * extent);
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i)
      g.vertices.push_back(glm::vec3(float(-extent + 2.0 * extent * i / n), float(bump(rng)),
                                     float(-extent + 2.0 * extent * j / n)));
  auto id = [n](int i, int j) { return unsigned(j * (n + 1) + i); };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      g.triangles.push_back({id(i, j), id(i + 1, j + 1), id(i + 1, j)});
      g.triangles.push_back({id(i, j), id(i, j + 1), id(i + 1, j + 1)});
    }
  return g;
}

} // namespace masq
