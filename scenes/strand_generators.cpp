#include "scenes/strand_generators.h"
#include "masq/error.h"
#include "scenes/prim_table.h"
#include <algorithm>
#include <cmath>
#include <random>
#include <string>

namespace masq {

namespace {

using Rng = std::mt19937_64;

glm::dvec3 unit_vector(Rng& rng) {
  std::normal_distribution<double> g;
  for (;;) {
    glm::dvec3 v(g(rng), g(rng), g(rng));
    double l = glm::length(v);
    if (l > 1e-9) return v / l;
  }
}

glm::dvec3 any_perpendicular(const glm::dvec3& w) {
  glm::dvec3 h = std::abs(w.x) < 0.6 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
  return glm::normalize(glm::cross(w, h));
}

Camera framing(const glm::dvec3& lo, const glm::dvec3& hi) {
  Camera c;
  glm::dvec3 centre = 0.5 * (lo + hi);
  double size = glm::length(hi - lo);
  c.target = centre;
  c.eye = centre + glm::dvec3(0.0, 0.25 * size, -1.6 * size);
  c.fov_y_deg = 40.0;
  return c;
}

void bounds(const std::vector<Strand>& s, glm::dvec3& lo, glm::dvec3& hi) {
  lo = glm::dvec3(INFINITY);
  hi = glm::dvec3(-INFINITY);
  for (const Strand& st : s)
    for (const glm::dvec3& p : st.points) {
      lo = glm::min(lo, p);
      hi = glm::max(hi, p);
    }
}

} // namespace

Geometry strands_to_geometry(const std::vector<Strand>& strands, PrimType type) {
  const ScenePrimRow& row = scene_prim_row(type);
  if (!row.add_strand_piece) throw Error(std::string("strands: cannot make ") + prim_type_name(type) + "s");
  Geometry g;
  g.type = type;
  for (const Strand& s : strands) {
    const std::size_t n = s.points.size();
    if (s.radii.size() != n) throw Error("strands: a strand has " + std::to_string(n) + " points but " +
                                         std::to_string(s.radii.size()) + " radii");
    for (std::size_t i = 0; i + 1 < n; ++i) row.add_strand_piece(g, s, i);
  }
  return g;
}

std::vector<Strand> grow_hair(const HairParams& p) {
  if (p.strands < 1 || p.points < 2 || !(p.length > 0) || !(p.radius > 0))
    throw Error("hair: strands >= 1, points >= 2, length > 0 and radius > 0 are required");
  Rng rng(p.seed);
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  std::vector<Strand> out;
  out.reserve(std::size_t(p.strands));
  const glm::dvec3 scale = p.surface == HairSurface::Body ? glm::dvec3(2, 1, 1) : glm::dvec3(1);
  while (int(out.size()) < p.strands) {
    glm::dvec3 u = unit_vector(rng);
    if (p.surface == HairSurface::Head && u.y < -0.1) continue; // scalp: the upper half
    glm::dvec3 root = u * scale;
    glm::dvec3 normal = glm::normalize(u / scale);
    glm::dvec3 side = any_perpendicular(normal), side2 = glm::cross(normal, side);
    double phase = 2.0 * M_PI * uni(rng);
    double seg = p.length / (p.points - 1);
    Strand s;
    glm::dvec3 dir = normal, pos = root;
    for (int k = 0; k < p.points; ++k) {
      double f = double(k) / (p.points - 1);
      // Curl: a helix around the growth direction.
      double ang = phase + 2.0 * M_PI * p.curl_turns * f;
      glm::dvec3 offset = p.curl * p.length * (std::cos(ang) * side + std::sin(ang) * side2) * f;
      s.points.push_back(pos + offset);
      s.radii.push_back(p.radius * (1.0 - 0.5 * f));
      dir = glm::normalize(dir + p.gravity * seg / p.length * glm::dvec3(0, -1, 0) * 3.0 + p.noise * unit_vector(rng) * 0.3);
      pos += seg * dir;
    }
    out.push_back(std::move(s));
  }
  return out;
}

Scene make_hair_scene(const HairParams& p) {
  std::vector<Strand> strands = grow_hair(p);
  Scene s;
  s.name = std::string(p.surface == HairSurface::Body ? "fur" : "hair") + " (" + std::to_string(p.strands) + " strands)";
  s.geometries.push_back(strands_to_geometry(strands, p.type));
  s.instances.push_back({0, {}});
  glm::dvec3 lo, hi;
  bounds(strands, lo, hi);
  s.camera = framing(lo, hi);
  return s;
}

std::vector<Strand> trace_streamlines(const StreamlineParams& p) {
  if (p.lines < 1 || p.steps < 1 || !(p.step > 0) || !(p.radius > 0))
    throw Error("streamlines: lines >= 1, steps >= 1, step > 0 and radius > 0 are required");
  // ABC flow with A = 1, B = sqrt(2/3), C = sqrt(1/3), on a domain scaled by pi.
  const double A = 1.0, B = std::sqrt(2.0 / 3.0), C = std::sqrt(1.0 / 3.0);
  auto flow = [&](const glm::dvec3& x) {
    glm::dvec3 q = M_PI * x;
    return glm::dvec3(A * std::sin(q.z) + C * std::cos(q.y), B * std::sin(q.x) + A * std::cos(q.z),
                      C * std::sin(q.y) + B * std::cos(q.x));
  };
  Rng rng(p.seed);
  std::uniform_real_distribution<double> uni(-1.0, 1.0);
  std::vector<Strand> out;
  for (int l = 0; l < p.lines; ++l) {
    Strand s;
    glm::dvec3 x(uni(rng), uni(rng), uni(rng));
    for (int k = 0; k <= p.steps; ++k) {
      glm::dvec3 v = flow(x);
      double speed = glm::length(v);
      s.points.push_back(x);
      s.radii.push_back(p.radius * (1.0 / (0.5 + 0.5 * speed)));
      // RK4 on the normalised field: equal arc length per step.
      auto f = [&](const glm::dvec3& y) {
        glm::dvec3 w = flow(y);
        double n = glm::length(w);
        return n > 1e-12 ? w / n : glm::dvec3(0);
      };
      glm::dvec3 k1 = f(x), k2 = f(x + 0.5 * p.step * k1), k3 = f(x + 0.5 * p.step * k2), k4 = f(x + p.step * k3);
      x += p.step / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
    }
    out.push_back(std::move(s));
  }
  return out;
}

Scene make_streamline_scene(const StreamlineParams& p) {
  std::vector<Strand> lines = trace_streamlines(p);
  Scene s;
  s.name = "streamlines (" + std::to_string(p.lines) + " ABC-flow lines)";
  s.geometries.push_back(strands_to_geometry(lines, p.type));
  s.instances.push_back({0, {}});
  glm::dvec3 lo, hi;
  bounds(lines, lo, hi);
  s.camera = framing(lo, hi);
  return s;
}

std::vector<Strand> make_random_tubes(int count, int points, double radius, std::uint64_t seed) {
  Rng rng(seed);
  std::uniform_real_distribution<double> uni(-1.0, 1.0), r01(0.3, 1.0);
  std::vector<Strand> out;
  for (int i = 0; i < count; ++i) {
    Strand s;
    glm::dvec3 x(uni(rng), uni(rng), uni(rng)), dir = unit_vector(rng);
    for (int k = 0; k < points; ++k) {
      s.points.push_back(x);
      s.radii.push_back(radius * r01(rng));
      dir = glm::normalize(dir + 0.4 * unit_vector(rng));
      x += 0.05 * dir;
    }
    out.push_back(std::move(s));
  }
  return out;
}

} // namespace masq
