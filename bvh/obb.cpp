#include "bvh/obb.h"
#include "scenes/error.h"
#include <cmath>

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
  Aabb box;
  glm::dvec3 pa = xf.apply_point(glm::dvec3(c.a)), pb = xf.apply_point(glm::dvec3(c.b));
  glm::dvec3 ext;
  for (int k = 0; k < 3; ++k)
    ext[k] = double(c.radius) * glm::length(glm::dvec3(xf.linear[0][k], xf.linear[1][k], xf.linear[2][k]));
  box.grow(pa - ext);
  box.grow(pa + ext);
  box.grow(pb - ext);
  box.grow(pb + ext);
  return box;
}

namespace {

// Largest |coordinate| of the capsule in unit space under the stored map m composed
// with object_to_world: max over both endpoints of |G_k x + g_k| + r |G_k|.
double unit_extent(const CapsulePrim& c, const Affine3& xf, const Mat3x4f& m) {
  Affine3 stored = from_mat3x4f(m);
  glm::dmat3 g = stored.linear * xf.linear;
  glm::dvec3 t = stored.linear * xf.translation + stored.translation;
  double worst = 0.0;
  for (int k = 0; k < 3; ++k) {
    glm::dvec3 row(g[0][k], g[1][k], g[2][k]);
    double support = double(c.radius) * glm::length(row);
    for (glm::dvec3 p : {glm::dvec3(c.a), glm::dvec3(c.b)})
      worst = std::max(worst, std::abs(glm::dot(row, p) + t[k]) + support);
  }
  return worst;
}

} // namespace

MasqueradeBox capsule_masquerade_box(const CapsulePrim& c, const Affine3& xf) {
  if (!(c.radius > 0.0f)) throw Error("obb: a capsule of radius 0 has no oriented box");
  glm::dvec3 a(c.a), b(c.b);
  glm::dvec3 axis = b - a;
  double len = glm::length(axis);
  glm::dvec3 w = len > 0.0 ? axis / len : glm::dvec3(0, 0, 1);
  // Any unit vector perpendicular to w (Frisvad-style branch on the largest component).
  glm::dvec3 helper = std::abs(w.x) < 0.6 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
  glm::dvec3 u1 = glm::normalize(glm::cross(w, helper));
  glm::dvec3 u2 = glm::cross(w, u1);
  double r = c.radius;
  glm::dvec3 half(0.5 * len + r, r, r);
  // unit -> object: x = center + R * diag(half) * u.
  Affine3 unit_to_object;
  unit_to_object.linear = glm::dmat3(w * half.x, u1 * half.y, u2 * half.z);
  unit_to_object.translation = 0.5 * (a + b);
  Affine3 unit_to_world;
  unit_to_world.linear = xf.linear * unit_to_object.linear;
  unit_to_world.translation = xf.apply_point(unit_to_object.translation);
  Affine3 world_to_unit = inverse(unit_to_world);

  MasqueradeBox out;
  // Round to fp32, then shrink the map until the stored matrix provably maps the
  // capsule inside [-1,1]^3 (rounding can push it out by a few ulps).
  double shrink = 1.0;
  for (int attempt = 0; attempt < 8; ++attempt) {
    Affine3 scaled = world_to_unit;
    scaled.linear *= shrink;
    scaled.translation *= shrink;
    out.world_to_unit = to_mat3x4f(scaled);
    double e = unit_extent(c, xf, out.world_to_unit);
    if (e <= 1.0) break;
    shrink *= (1.0 - 4.0 * 5.96e-8) / e;
    if (attempt == 7) throw Error("obb: could not fit a conservative fp32 masquerade transform");
  }
  out.unit_to_world = to_mat3x4f(inverse(from_mat3x4f(out.world_to_unit)));
  out.world_box = Aabb::intersect(capsule_world_box(c, xf), [&] {
    Aabb corners;
    Affine3 u2w = inverse(from_mat3x4f(out.world_to_unit));
    for (int i = 0; i < 8; ++i)
      corners.grow(u2w.apply_point(glm::dvec3(i & 1 ? 1 : -1, i & 2 ? 1 : -1, i & 4 ? 1 : -1)));
    return corners;
  }());
  glm::dvec3 e0 = unit_to_world.linear[0], e1 = unit_to_world.linear[1], e2 = unit_to_world.linear[2];
  out.obb_area = 8.0 * (glm::length(glm::cross(e0, e1)) + glm::length(glm::cross(e1, e2)) + glm::length(glm::cross(e2, e0)));
  return out;
}

} // namespace masq
