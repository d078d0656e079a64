// Primitive-level long-double ground truth: one ray against one primitive, in the
// primitive's object space. Shares no code with kernels/ (it is what they are checked
// against). Each type is in oracle/oracle_<type>.cpp, written from the geometry, not
// from any fast-path formula in kernels/. Contract, identical for every type and for the
// GPU kernels:
//  - The primitive is a closed solid; a hit is a crossing of its boundary at ray
//    parameter t (point o + t d; d need not be unit length). The nearest crossing with
//    t in [max(tmin, t_self), tmax] is reported, so a ray starting inside reports its
//    exit. t_self = self_window_t(r, o - centre, dot(d, d), span).
//  - centre: capsule/cone: midpoint of a and b; sphere: center; curve: mean of the four
//    control points; triangle: v0 (and r = 0). r: the radius (cone: max(ra, rb)).
//  - Radius 0 (negative radii count as 0): no surface, never hit. Zero-length capsule =
//    sphere; coincident curve control points = sphere; a cone whose one sphere contains
//    the other = the bigger sphere.
//  - Invalid rays (NaN/Inf in o or d, d = 0, NaN limits, tmin > tmax): miss.
//  - Normals: outward, unit (triangles: the winding normal (v1-v0) x (v2-v0)).
//  - Ribbons are flat like triangles (no inside; centre the midpoint of p0 p1, r = 0 in
//    the window, span |p1 - p0|; the triangles' plane rule); normal: n's side of the
//    plane; u: axial parameter, v: width coordinate over the half-width, in [-1, 1]. A
//    normal within 2^-12 rad of the axis, a zero axis or zero widths: no surface.
#pragma once
#include "scenes/scene.h"
#include <limits>

namespace masq::oracle {

using ld = long double;

struct Vld {
  ld x = 0, y = 0, z = 0;
};

struct PrimRay {
  Vld o, d;
  ld tmin = 0, tmax = std::numeric_limits<ld>::infinity();
};

struct PrimResult {
  bool hit = false;
  ld t = std::numeric_limits<ld>::infinity();
  Vld normal;  // outward unit normal at the hit (object space of the primitive)
  ld u = 0;    // capsule/cone: axial parameter in [0,1]; curve: curve parameter s; triangle: barycentric u
  ld v = 0;    // triangle: barycentric v
  // Relative near-miss measure of this primitive for this ray, over the whole ray
  // segment [tmin, tmax]: |min distance(ray line segment, primitive core) - r| / r
  // (for triangles: smallest |barycentric| at the plane crossing). Small values mark
  // rays where fp32 may legitimately flip hit and miss.
  ld clearance = std::numeric_limits<ld>::infinity();
  ld t_near = std::numeric_limits<ld>::infinity(); // ray parameter of that closest approach
};

PrimResult oracle_capsule(const CapsulePrim& p, const PrimRay& ray);
PrimResult oracle_round_cone(const RoundConePrim& p, const PrimRay& ray);
PrimResult oracle_sphere(const SpherePrim& p, const PrimRay& ray);
PrimResult oracle_curve(const CurvePrim& p, const PrimRay& ray);
PrimResult oracle_ribbon(const RibbonPrim& p, const PrimRay& ray);
PrimResult oracle_triangle(const glm::vec3& v0, const glm::vec3& v1, const glm::vec3& v2, const PrimRay& ray);

// The self-intersection window every intersector applies:
//   t_self = (2^-10 * radius + 32 * 2^-24 * (|o - centre| + span)) / sqrt(dd),  dd = dot(d, d);
//   span: capsule and cone |b - a|, curve the control polygon's length, else 0.
ld self_window_t(ld radius, Vld o_minus_centre, ld dd, ld span = 0);

} // namespace masq::oracle
