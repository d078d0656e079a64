#include "bvh/bounds/obb.h"
#include "scenes/prim_table.h"
#include "masq/error.h"
#include <algorithm>
#include <cmath>
#include <utility>

namespace masq {

Affine3 inverse(const Affine3& a) {
  Affine3 r;
  r.linear = glm::inverse(a.linear);
  r.translation = -(r.linear * a.translation);
  return r;
}

Mat3x4f to_mat3x4f(const Affine3& a) {
  Mat3x4f m{};
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) m[4 * r + c] = float(a.linear[c][r]); // glm is column-major
    m[4 * r + 3] = float(a.translation[r]);
  }
  return m;
}

Affine3 from_mat3x4f(const Mat3x4f& m) {
  Affine3 a;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) a.linear[c][r] = m[4 * r + c];
    a.translation[r] = m[4 * r + 3];
  }
  return a;
}

Aabb capsule_world_box(const CapsulePrim& c, const Affine3& xf) {
  Geometry g;
  g.type = PrimType::Capsule;
  g.capsules.push_back(c);
  return hull_world_box(ball_hull(g, 0), xf);
}

namespace {

// Any unit vector perpendicular to unit w (branch on the largest component).
glm::dvec3 perpendicular(const glm::dvec3& w) {
  glm::dvec3 helper = std::abs(w.x) < 0.6 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
  return glm::normalize(glm::cross(w, helper));
}

// First usable direction among the hull's centre differences (chord first).
glm::dvec3 main_axis(const BallHull& h) {
  const int n = h.count;
  const std::pair<int, int> tries[] = {{0, n - 1}, {0, 2}, {1, n - 1}, {0, 1}, {1, 2}, {2, n - 1}};
  for (auto [i, j] : tries) {
    if (i >= n || j >= n || i == j) continue;
    glm::dvec3 d = h.centre[j] - h.centre[i];
    double l = glm::length(d);
    if (l > 0.0) return d / l;
  }
  return {0, 0, 1};
}

// Fit centre and half extents along fixed axes to the hull's support.
ObbFrame fit_along(const BallHull& h, const glm::dmat3& axes) {
  ObbFrame f;
  f.axes = axes;
  for (int k = 0; k < 3; ++k) {
    double hi = h.support(axes[k]);
    double lo = -h.support(-axes[k]);
    f.centre += 0.5 * (hi + lo) * axes[k];
    f.half[k] = 0.5 * (hi - lo);
  }
  return f;
}

// A curve's axes (the chord, then the control polygon's largest offset from it) and that
// offset: the largest distance of a control point from the chord line through p0.
struct CurveChord {
  glm::dmat3 axes;
  double far = 0.0;
};
CurveChord curve_chord(const BallHull& h) {
  CurveChord c;
  glm::dvec3 w = main_axis(h);
  // Perpendicular offsets of the control points from the chord line through p0.
  glm::dvec3 far_dir(0.0);
  for (int i = 0; i < h.count; ++i) {
    glm::dvec3 q = h.centre[i] - h.centre[0];
    glm::dvec3 perp = q - glm::dot(q, w) * w;
    double l = glm::length(perp);
    if (l > c.far) {
      c.far = l;
      far_dir = perp / l;
    }
  }
  // Offsets far below the radius are rounding noise of nearly collinear control points:
  // their direction is not perpendicular to w (a 1e-5-long piece of a subdivided strand
  // gave u1 == w and a singular box), and they do not matter for the box anyway.
  glm::dvec3 u1 = perpendicular(w);
  if (c.far > 1e-6 * hull_max_radius(h)) {
    glm::dvec3 o = far_dir - glm::dot(far_dir, w) * w;
    if (glm::length(o) > 0.5) u1 = glm::normalize(o);
  }
  c.axes = glm::dmat3(w, u1, glm::cross(w, u1));
  return c;
}

ObbFrame curve_obb_fit(const BallHull& h, CurveObb mode) {
  const CurveChord chord = curve_chord(h);
  ObbFrame f = fit_along(h, chord.axes);
  if (mode == CurveObb::Tight) return f;
  // paper: a cylinder around the chord of radius (largest control-point distance + r),
  // boxed with a square cross-section centred on the chord.
  const glm::dvec3 w = chord.axes[0];
  double radial = chord.far + hull_max_radius(h);
  double axial_centre = glm::dot(f.centre - h.centre[0], w);
  f.centre = h.centre[0] + axial_centre * w;
  f.half.y = radial;
  f.half.z = radial;
  return f;
}

// Largest |coordinate| of the hull in unit space under the stored map m composed with
// object_to_world: max over the rows k of the support in both directions.
double unit_extent(const BallHull& h, const Affine3& xf, const Mat3x4f& m) {
  Affine3 stored = from_mat3x4f(m);
  glm::dmat3 g = stored.linear * xf.linear;
  glm::dvec3 t = stored.linear * xf.translation + stored.translation;
  double worst = 0.0;
  for (int k = 0; k < 3; ++k) {
    glm::dvec3 row(g[0][k], g[1][k], g[2][k]);
    // Two support calls, not one support_pair (the same bits, and half the work): with
    // the pair, GCC 12.2 at -O3 made maps that leave capsules outside the unit box
    // (Obb.CapsuleMapsInsideUnitBoxAndTouchesIt fails); -O2, or -O3 with
    // -fno-tree-slp-vectorize, passes. A miscompile or undefined behaviour not found yet.
    worst = std::max({worst, std::abs(h.support(row) + t[k]), std::abs(-h.support(-row) + t[k])});
  }
  return worst;
}

} // namespace

glm::dmat3 primitive_obb_axes(const Geometry& g, const BallHull& h) {
  const PrimShape shape = scene_prim_row(g.type).shape;
  if (shape == PrimShape::Ball) return glm::dmat3(1.0);
  if (shape == PrimShape::Bezier) return curve_chord(h).axes;
  glm::dvec3 w = main_axis(h);
  glm::dvec3 u1 = perpendicular(w);
  return glm::dmat3(w, u1, glm::cross(w, u1));
}

ObbFrame primitive_obb(const Geometry& g, std::size_t prim, CurveObb curve_obb) {
  return primitive_obb(g, ball_hull(g, prim), curve_obb);
}

ObbFrame primitive_obb(const Geometry& g, const BallHull& h, CurveObb curve_obb) {
  if (scene_prim_row(g.type).shape == PrimShape::Bezier) return curve_obb_fit(h, curve_obb);
  return fit_along(h, primitive_obb_axes(g, h));
}

MasqueradeBox masquerade_box(const Geometry& g, std::size_t prim, const Affine3& xf, CurveObb curve_obb) {
  BallHull h = ball_hull(g, prim);
  if (!(hull_max_radius(h) > 0.0))
    throw Error(std::string("obb: a ") + prim_type_name(g.type) + " of radius 0 has no oriented box");
  ObbFrame f = primitive_obb(g, prim, curve_obb);
  // unit -> object: x = centre + axes * diag(half) * u.
  Affine3 unit_to_object;
  unit_to_object.linear = glm::dmat3(f.axes[0] * f.half.x, f.axes[1] * f.half.y, f.axes[2] * f.half.z);
  unit_to_object.translation = f.centre;
  Affine3 unit_to_world;
  unit_to_world.linear = xf.linear * unit_to_object.linear;
  unit_to_world.translation = xf.apply_point(unit_to_object.translation);
  Affine3 world_to_unit = inverse(unit_to_world);

  Mat3x4f stored;
  // Round to fp32, then shrink the map until the stored matrix provably maps the
  // primitive inside [-1,1]^3. Rounding can push it out by a few ulps of the map's
  // largest entry, and re-rounding after a shrink errs again by as much (for a thin
  // primitive far from the origin the translation is ~|c|/r unit boxes), so each retry
  // shrinks by twice the previous excess.
  double shrink = 1.0;
  for (int attempt = 0;; ++attempt) {
    Affine3 scaled = world_to_unit;
    scaled.linear *= shrink;
    scaled.translation *= shrink;
    stored = to_mat3x4f(scaled);
    double e = unit_extent(h, xf, stored);
    if (e <= 1.0) break;
    if (attempt == 24 || !std::isfinite(e)) throw Error("obb: could not fit a conservative fp32 masquerade transform");
    shrink *= (1.0 - 4.0 * 5.96e-8) / (1.0 + double(1 << attempt) * (e - 1.0));
  }
  std::optional<MasqueradeBox> done = complete_masquerade_box(from_mat3x4f(stored), hull_world_box(h, xf));
  if (!done)
    throw Error(std::string("obb: the oriented box of a ") + prim_type_name(g.type) + " came out empty or not finite");
  return *done;
}

std::optional<MasqueradeBox> complete_masquerade_box(const Affine3& world_to_unit, const Aabb& exact) {
  MasqueradeBox out;
  const Affine3 u2w = inverse(world_to_unit);
  out.world_to_unit = to_mat3x4f(world_to_unit);
  out.unit_to_world = to_mat3x4f(u2w);
  Aabb corners;
  for (int i = 0; i < 8; ++i) corners.grow(u2w.apply_point(glm::dvec3(i & 1 ? 1 : -1, i & 2 ? 1 : -1, i & 4 ? 1 : -1)));
  out.world_box = Aabb::intersect(exact, corners);
  for (int k = 0; k < 3; ++k)
    if (!(out.world_box.lo[k] <= out.world_box.hi[k]) || !std::isfinite(out.world_box.lo[k]) ||
        !std::isfinite(out.world_box.hi[k]))
      return std::nullopt;
  const glm::dvec3 e0 = u2w.linear[0], e1 = u2w.linear[1], e2 = u2w.linear[2];
  out.obb_area = 8.0 * (glm::length(glm::cross(e0, e1)) + glm::length(glm::cross(e1, e2)) + glm::length(glm::cross(e2, e0)));
  out.aabb_area = exact.area();
  return out;
}

MasqueradeBox capsule_masquerade_box(const CapsulePrim& c, const Affine3& xf) {
  Geometry g;
  g.type = PrimType::Capsule;
  g.capsules.push_back(c);
  return masquerade_box(g, 0, xf);
}

} // namespace masq
