#include "scenes/curve_tools.h"
#include "masq/error.h"
#include "scenes/prim_table.h"
#include "scenes/strand_generators.h"
#include <string>

namespace masq {

namespace {
std::array<glm::dvec3, 4> control(const CurvePrim& c) {
  return {glm::dvec3(c.p[0]), glm::dvec3(c.p[1]), glm::dvec3(c.p[2]), glm::dvec3(c.p[3])};
}

// The piece [s0, s1] of a cubic as its own control points (blossoming).
std::array<glm::dvec3, 4> piece(const std::array<glm::dvec3, 4>& p, double s0, double s1) {
  auto blossom = [&](double a, double b, double c) {
    auto lerp = [](glm::dvec3 x, glm::dvec3 y, double t) { return x + (y - x) * t; };
    glm::dvec3 q0 = lerp(p[0], p[1], a), q1 = lerp(p[1], p[2], a), q2 = lerp(p[2], p[3], a);
    glm::dvec3 r0 = lerp(q0, q1, b), r1 = lerp(q1, q2, b);
    return lerp(r0, r1, c);
  };
  return {blossom(s0, s0, s0), blossom(s0, s0, s1), blossom(s0, s1, s1), blossom(s1, s1, s1)};
}
// A geometry of cubic Bezier curves (what subdivide_curves and curves_to_segments rewrite).
bool holds_curves(const Geometry& g) { return scene_prim_row(g.type).shape == PrimShape::Bezier; }
} // namespace

glm::dvec3 bezier_point(const CurvePrim& c, double s) {
  auto p = control(c);
  double t = 1.0 - s;
  return t * t * t * p[0] + 3.0 * t * t * s * p[1] + 3.0 * t * s * s * p[2] + s * s * s * p[3];
}

Scene subdivide_curves(const Scene& scene, int k) {
  if (k < 1) throw Error("subdivide_curves: k = " + std::to_string(k) + " (must be >= 1)");
  Scene out = scene;
  if (k == 1) return out;
  for (Geometry& g : out.geometries) {
    if (!holds_curves(g)) continue;
    std::vector<CurvePrim> split;
    split.reserve(g.curves.size() * std::size_t(k));
    for (const CurvePrim& c : g.curves) {
      auto p = control(c);
      for (int i = 0; i < k; ++i) {
        auto q = piece(p, double(i) / k, double(i + 1) / k);
        CurvePrim n{};
        for (int j = 0; j < 4; ++j) n.p[std::size_t(j)] = glm::vec3(q[std::size_t(j)]);
        n.radius = c.radius;
        split.push_back(n);
      }
    }
    g.curves = std::move(split);
  }
  out.name = scene.name + " (curves x" + std::to_string(k) + ")";
  return out;
}

Scene curves_to_segments(const Scene& scene, int n, PrimType type) {
  if (n < 1) throw Error("curves_to_segments: n = " + std::to_string(n) + " (must be >= 1)");
  const ScenePrimRow& row = scene_prim_row(type);
  if (!row.add_segment) throw Error(std::string("curves_to_segments: cannot make ") + prim_type_name(type) + "s");
  Scene out = scene;
  for (Geometry& g : out.geometries) {
    if (!holds_curves(g)) continue;
    Geometry seg;
    seg.type = type;
    for (const CurvePrim& c : g.curves)
      for (int i = 0; i < n; ++i) {
        glm::vec3 a(bezier_point(c, double(i) / n)), b(bezier_point(c, double(i + 1) / n));
        row.add_segment(seg, a, c.radius, b, c.radius); // a capsule's mean of equal radii is the radius
      }
    g = std::move(seg);
  }
  out.name = scene.name + " (curves as " + std::to_string(n) + " " + prim_type_name(type) + "s)";
  return out;
}

namespace {

// The first and last hull balls of primitive i: where it starts and ends along its axis
// (a segment's two balls, a curve's first and last control points).
std::array<PrimBall, 2> prim_ends(const ScenePrimRow& row, const Geometry& g, std::size_t i) {
  PrimBalls balls;
  const int n = row.balls(g, i, balls);
  return {balls[0], balls[std::size_t(n - 1)]};
}

// Whether a primitive starting at `next` continues the strand of one ending at `prev`:
// the loaders write a strand's segments in order, each starting at the last one's end.
bool continues_strand(const std::array<PrimBall, 2>& prev, const std::array<PrimBall, 2>& next) {
  return prev[1].centre == next[0].centre;
}

// Chains consecutive segments sharing an end point into strands: segment i is the hull of
// its two balls (scene_prim_row's balls of a Segment-shaped type).
std::vector<Strand> chain_segments(const Geometry& g) {
  const ScenePrimRow& row = scene_prim_row(g.type);
  std::vector<Strand> strands;
  std::array<PrimBall, 2> prev{};
  for (std::size_t i = 0; i < row.count(g); ++i) {
    const std::array<PrimBall, 2> ends = prim_ends(row, g, i);
    if (i == 0 || !continues_strand(prev, ends))
      strands.push_back({{glm::dvec3(ends[0].centre)}, {double(ends[0].radius)}});
    strands.back().points.push_back(glm::dvec3(ends[1].centre));
    strands.back().radii.push_back(double(ends[1].radius));
    prev = ends;
  }
  return strands;
}

} // namespace

Scene segments_to_curves(const Scene& scene) {
  Scene out = scene;
  for (Geometry& g : out.geometries)
    if (scene_prim_row(g.type).shape == PrimShape::Segment) g = strands_to_geometry(chain_segments(g), PrimType::Curve);
  out.name = scene.name + " (as curves)";
  return out;
}

std::vector<std::uint32_t> strand_ids(const Geometry& g) {
  const ScenePrimRow& row = scene_prim_row(g.type);
  std::vector<std::uint32_t> ids;
  if (!row.oriented) return ids;
  ids.resize(row.count(g));
  std::array<PrimBall, 2> prev{};
  std::uint32_t strand = 0;
  for (std::size_t i = 0; i < ids.size(); ++i) {
    const std::array<PrimBall, 2> ends = prim_ends(row, g, i);
    if (i > 0 && !continues_strand(prev, ends)) ++strand;
    ids[i] = strand;
    prev = ends;
  }
  return ids;
}

} // namespace masq
