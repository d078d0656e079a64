#include "stress/stress_prim_rows.h"
#include "scenes/prim_table.h"
#include "masq/error.h"
#include <algorithm>
#include <cmath>
#include <string>

namespace masq::stress {

namespace {

// ---- Placing one primitive (no draws: the builder drew the place) ----

void add_capsule(const CellSpec&, const PrimPlace& at, Geometry& g, Probe& pr) {
  g.capsules.push_back({glm::vec3(at.a), glm::vec3(at.e), at.rf});
  pr.p = {glm::dvec3(glm::vec3(at.a)), glm::dvec3(glm::vec3(at.e))};
  pr.ra = pr.rb = at.rf;
}

void add_round_cone(const CellSpec& c, const PrimPlace& at, Geometry& g, Probe& pr) {
  float rb = 0.5f * at.rf;
  glm::dvec3 e = at.e;
  if (c.degenerate == "contained") e = at.a + 0.3 * at.r * at.w; // ball b inside ball a
  g.round_cones.push_back({glm::vec3(at.a), at.rf, glm::vec3(e), rb});
  pr.p = {glm::dvec3(glm::vec3(at.a)), glm::dvec3(glm::vec3(e))};
  pr.ra = at.rf;
  pr.rb = rb;
}

void add_curve(const CellSpec& c, const PrimPlace& at, Geometry& g, Probe& pr) {
  const glm::dvec3 &a = at.a, &e = at.e, &m = at.m, &centre = at.centre;
  const double L = at.L, r = at.r;
  CurvePrim cv{};
  std::array<glm::dvec3, 4> q = {a, a + (e - a) / 3.0 + 0.15 * L * m, a + 2.0 * (e - a) / 3.0 - 0.1 * L * m, e};
  if (c.degenerate == "coincident") q = {centre, centre, centre, centre};
  if (c.degenerate == "flat-tangent") q = {a, a, e, e};
  if (c.degenerate == "bend") q = {a, e, e + 2.5 * r * m, a + 2.5 * r * m};
  if (c.degenerate == "cusp") // (0,0) (1,1) (0,1) (1,0) in (w, m): C'(1/2) = 0
    q = {a, e + L * m, a + L * m, e};
  if (c.degenerate == "fold") q = {a, e, e, a};
  for (int k = 0; k < 4; ++k) {
    cv.p[std::size_t(k)] = glm::vec3(q[std::size_t(k)]);
    pr.p[std::size_t(k)] = glm::dvec3(cv.p[std::size_t(k)]);
  }
  cv.radius = at.rf;
  g.curves.push_back(cv);
  pr.ra = pr.rb = at.rf;
}

void add_sphere(const CellSpec&, const PrimPlace& at, Geometry& g, Probe& pr) {
  g.spheres.push_back({glm::vec3(at.centre), at.rf});
  pr.p = {glm::dvec3(glm::vec3(at.centre))};
  pr.ra = pr.rb = at.rf;
}

// A ribbon along the cell's axis, narrowing to half its width, facing m; its probe keeps
// the normal in p[2] (the aims need the plane).
void add_ribbon(const CellSpec& c, const PrimPlace& at, Geometry& g, Probe& pr) {
  float rb = 0.5f * at.rf;
  glm::dvec3 n = c.degenerate == "normal-along-axis" ? at.w : at.m;
  g.ribbons.push_back({glm::vec3(at.a), at.rf, glm::vec3(at.e), rb, glm::vec3(n)});
  pr.p = {glm::dvec3(glm::vec3(at.a)), glm::dvec3(glm::vec3(at.e)), glm::dvec3(glm::vec3(n))};
  pr.ra = at.rf;
  pr.rb = rb;
}

void add_triangle(const CellSpec& c, const PrimPlace& at, Geometry& g, Probe& pr) {
  glm::dvec3 v0 = at.a, v1 = at.e, v2 = at.centre + 0.8 * at.L * at.m;
  if (c.degenerate == "collinear") v2 = v1; // two coincident vertices: no area
  unsigned base = unsigned(g.vertices.size());
  for (const glm::dvec3& v : {v0, v1, v2}) g.vertices.push_back(glm::vec3(v));
  g.triangles.push_back({base, base + 1, base + 2});
  pr.p = {glm::dvec3(glm::vec3(v0)), glm::dvec3(glm::vec3(v1)), glm::dvec3(glm::vec3(v2))};
  pr.ra = pr.rb = 0;
}

// ---- The core: points, tangents, radii ----

// Along p0 -> p1. A sphere's p1 is 0, so its "axis" points from its centre to the
// origin: only a direction grazing rays are drawn about.
glm::dvec3 linear_point(const Probe& pr, double s) { return pr.p[0] + s * (pr.p[1] - pr.p[0]); }
glm::dvec3 linear_axis(const Probe& pr, double) { return pr.p[1] - pr.p[0]; }
glm::dvec3 centre_point(const Probe& pr, double) { return pr.p[0]; }

glm::dvec3 bezier_point(const Probe& pr, double s) {
  double t = 1 - s;
  return t * t * t * pr.p[0] + 3 * t * t * s * pr.p[1] + 3 * t * s * s * pr.p[2] + s * s * s * pr.p[3];
}
glm::dvec3 bezier_axis(const Probe& pr, double s) {
  double t = 1 - s;
  glm::dvec3 d = 3 * t * t * (pr.p[1] - pr.p[0]) + 6 * t * s * (pr.p[2] - pr.p[1]) + 3 * s * s * (pr.p[3] - pr.p[2]);
  if (glm::length(d) == 0) d = pr.p[3] - pr.p[0]; // a cusp or coincident points: the chord
  return d;
}

double constant_radius(const Probe& pr, double) { return pr.ra; }
double linear_radius(const Probe& pr, double s) { return pr.ra + s * (pr.rb - pr.ra); }

// ---- What a camera looks at ----

glm::dvec3 middle(const Probe& pr) { return pr.point(0.5); }
glm::dvec3 bezier_middle(const Probe& pr) { return 0.5 * (pr.p[0] + pr.p[3]); }
glm::dvec3 centroid(const Probe& pr) { return (pr.p[0] + pr.p[1] + pr.p[2]) / 3.0; }
glm::dvec3 linear_chord(const Probe& pr) { return pr.p[1] - pr.p[0]; }
glm::dvec3 bezier_chord(const Probe& pr) { return pr.p[3] - pr.p[0]; }
glm::dvec3 no_chord(const Probe&) { return glm::dvec3(0.0); } // a ball looks the same from anywhere

// ---- Aiming ----

// With an eye (camera cells) the direction is eye -> point; the kinds that choose their
// own direction (grazing, axis-parallel) are replaced by silhouette and random rays by
// the caller.
Aim aim_triangle(const Probe& pr, RayKind kind, const AimFrom& from, Rng& rng) {
  const double L = from.L;
  const glm::dvec3* eye = from.eye;
  glm::dvec3 e1 = pr.p[1] - pr.p[0], e2 = pr.p[2] - pr.p[0];
  glm::dvec3 n = glm::cross(e1, e2);
  double nl = glm::length(n);
  n = nl > 0 ? n / nl : glm::dvec3(0, 0, 1);
  double u = uniform(rng, 0, 1), v = uniform(rng, 0, 1);
  if (u + v > 1) {
    u = 1 - u;
    v = 1 - v;
  }
  glm::dvec3 inside = pr.p[0] + u * e1 + v * e2;
  switch (kind) {
    case RayKind::Silhouette: {
      // Just inside or outside an edge, relative offset 1e-6..1e-1 of the edge length.
      int k = int(uniform(rng, 0, 3));
      glm::dvec3 a = pr.p[std::size_t(k)], b = pr.p[std::size_t((k + 1) % 3)];
      glm::dvec3 mid = a + uniform(rng, 0, 1) * (b - a);
      glm::dvec3 towards = glm::normalize(inside - mid + 1e-30);
      double eps = std::pow(10.0, uniform(rng, -6, -1)) * L * (uniform(rng, 0, 1) < 0.5 ? -1 : 1);
      glm::dvec3 d = glm::normalize(n + 0.5 * random_unit(rng));
      glm::dvec3 at = mid + eps * towards;
      return {at, eye ? glm::normalize(at - *eye) : d};
    }
    case RayKind::Grazing: {
      glm::dvec3 t = perpendicular_to(n, rng);
      double ang = std::pow(10.0, uniform(rng, -4, -1));
      return {inside, glm::normalize(std::cos(ang) * t + std::sin(ang) * n)};
    }
    default: return {inside, eye ? glm::normalize(inside - *eye) : random_unit(rng)};
  }
}

// The primitives with a radius: rays pass the core at about r.
Aim aim_round(const Probe& pr, RayKind kind, const AimFrom& from, Rng& rng) {
  const glm::dvec3* eye = from.eye;
  const double spread = from.spread;
  // A ball has no axis: its rays aim about its centre, in random directions.
  const bool axis = scene_prim_row(pr.type).oriented;
  // s slightly beyond [0,1] reaches the end caps.
  double s = axis ? uniform(rng, -0.05, 1.05) : 0.0;
  double sc = std::clamp(s, 0.0, 1.0);
  glm::dvec3 q = pr.point(sc);
  glm::dvec3 w = pr.tangent(sc);
  double r = pr.radius(sc);
  double eps = std::pow(10.0, uniform(rng, -6, -1)) * (uniform(rng, 0, 1) < 0.5 ? -1 : 1);
  switch (kind) {
    case RayKind::Silhouette: {
      glm::dvec3 d = eye ? glm::normalize(q - *eye) : random_unit(rng);
      // Offset perpendicular to the ray and (on the tube) to the axis: the ray then
      // passes the axis at distance r (1 + eps) (from an eye, to first order in r / D).
      glm::dvec3 n = glm::cross(d, w);
      if (s != sc || !axis || glm::length(n) < 1e-3) n = perpendicular_to(d, rng);
      n = glm::normalize(n);
      glm::dvec3 at = q + r * (1 + eps) * n;
      return {at, eye ? glm::normalize(at - *eye) : d};
    }
    case RayKind::Grazing: {
      double ang = std::pow(10.0, uniform(rng, -4, -0.5));
      glm::dvec3 m = perpendicular_to(w, rng);
      glm::dvec3 d = glm::normalize(std::cos(ang) * w + std::sin(ang) * m);
      glm::dvec3 n = glm::normalize(glm::cross(d, m));
      return {q + r * (1 + eps) * n, d};
    }
    case RayKind::AxisParallel: {
      glm::dvec3 d(0.0);
      d[int(uniform(rng, 0, 3)) % 3] = uniform(rng, 0, 1) < 0.5 ? -1 : 1;
      return {q + 0.6 * spread * r * random_unit(rng) * uniform(rng, 0, 1), d};
    }
    default: {
      glm::dvec3 at = q + spread * r * random_unit(rng) * uniform(rng, 0, 1);
      return {at, eye ? glm::normalize(at - *eye) : random_unit(rng)};
    }
  }
}

// A flat strip: rays cross its plane near the long edges (|v| = r(s) (1 + eps)), graze
// the plane, or come from anywhere about the core.
Aim aim_ribbon(const Probe& pr, RayKind kind, const AimFrom& from, Rng& rng) {
  const glm::dvec3* eye = from.eye;
  const glm::dvec3 axis = pr.p[1] - pr.p[0];
  glm::dvec3 w = glm::cross(pr.p[2], axis);
  // No width direction (zero length, normal along the axis): any perpendicular will do.
  w = glm::length(w) > 1e-6 * glm::length(axis) && glm::length(w) > 0 ? glm::normalize(w) : perpendicular_to(pr.tangent(0), rng);
  const glm::dvec3 nrm = glm::normalize(glm::cross(pr.tangent(0), w) + 1e-300);
  double s = uniform(rng, -0.05, 1.05);
  double sc = std::clamp(s, 0.0, 1.0);
  glm::dvec3 q = pr.point(sc);
  double r = pr.radius(sc);
  double eps = std::pow(10.0, uniform(rng, -6, -1)) * (uniform(rng, 0, 1) < 0.5 ? -1 : 1);
  double side = uniform(rng, 0, 1) < 0.5 ? -1 : 1;
  switch (kind) {
    case RayKind::Silhouette: {
      glm::dvec3 at = q + side * r * (1 + eps) * w;
      glm::dvec3 d = glm::normalize(side * nrm + 0.5 * random_unit(rng));
      return {at, eye ? glm::normalize(at - *eye) : d};
    }
    case RayKind::Grazing: {
      double ang = std::pow(10.0, uniform(rng, -4, -0.5));
      double phi = uniform(rng, 0, 6.283185307179586);
      glm::dvec3 in_plane = std::cos(phi) * pr.tangent(sc) + std::sin(phi) * w;
      glm::dvec3 d = glm::normalize(std::cos(ang) * in_plane + side * std::sin(ang) * nrm);
      return {q + uniform(rng, -1, 1) * r * w, d};
    }
    case RayKind::AxisParallel: {
      glm::dvec3 d(0.0);
      d[int(uniform(rng, 0, 3)) % 3] = uniform(rng, 0, 1) < 0.5 ? -1 : 1;
      return {q + 0.6 * from.spread * r * random_unit(rng) * uniform(rng, 0, 1), d};
    }
    default: {
      glm::dvec3 at = q + from.spread * r * random_unit(rng) * uniform(rng, 0, 1);
      return {at, eye ? glm::normalize(at - *eye) : random_unit(rng)};
    }
  }
}

constexpr const char* kCapsuleDegenerates[] = {"zero-length", "zero-radius"};
constexpr const char* kRoundConeDegenerates[] = {"contained", "zero-length", "zero-radius"};
constexpr const char* kCurveDegenerates[] = {"coincident", "flat-tangent", "zero-radius"};
constexpr const char* kSphereDegenerates[] = {"zero-radius"};
constexpr const char* kTriangleDegenerates[] = {"collinear"};
constexpr const char* kRibbonDegenerates[] = {"normal-along-axis", "zero-length", "zero-radius"};
// Curves whose solid is not a tube about a smooth axis: a hairpin bent with a radius of
// curvature near r (its legs' balls overlap), a cusp (zero speed, the tangent turning by
// 180 degrees), and a control polygon folded back on itself.
constexpr const char* kCurveShapes[] = {"bend", "cusp", "fold"};

//  type, degenerates, shapes, sized_by_length, per_curve_isect, then the functions
constexpr StressPrimRow rows[] = {
    {PrimType::Triangle, kTriangleDegenerates, {}, true, false, add_triangle, linear_point, linear_axis,
     constant_radius, centroid, linear_chord, aim_triangle},
    {PrimType::Capsule, kCapsuleDegenerates, {}, false, false, add_capsule, linear_point, linear_axis, constant_radius,
     middle, linear_chord, aim_round},
    {PrimType::RoundCone, kRoundConeDegenerates, {}, false, false, add_round_cone, linear_point, linear_axis,
     linear_radius, middle, linear_chord, aim_round},
    {PrimType::Sphere, kSphereDegenerates, {}, false, false, add_sphere, centre_point, linear_axis, constant_radius,
     middle, no_chord, aim_round},
    {PrimType::Curve, kCurveDegenerates, kCurveShapes, false, true, add_curve, bezier_point, bezier_axis,
     constant_radius, bezier_middle, bezier_chord, aim_round},
    {PrimType::Ribbon, kRibbonDegenerates, {}, false, false, add_ribbon, linear_point, linear_axis, linear_radius,
     middle, linear_chord, aim_ribbon},
};
static_assert(one_row_per_prim_type(rows), "stress_prim_rows: one row per PrimType, in enum order");

} // namespace

const StressPrimRow& stress_prim_row(PrimType t) {
  const auto i = static_cast<std::size_t>(t);
  if (i >= prim_type_count) throw Error("stress: primitive type " + std::to_string(i) + " has no row");
  return rows[i];
}

glm::dvec3 Probe::point(double s) const { return stress_prim_row(type).point(*this, s); }

glm::dvec3 Probe::tangent(double s) const {
  glm::dvec3 d = stress_prim_row(type).axis(*this, s);
  double l = glm::length(d);
  return l > 0 ? d / l : glm::dvec3(0, 0, 1);
}

double Probe::radius(double s) const { return stress_prim_row(type).radius(*this, s); }

} // namespace masq::stress
