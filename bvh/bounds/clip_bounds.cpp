#include "bvh/bounds/clip_bounds.h"
#include "masq/error.h"
#include "scenes/prim_table.h"
#include <algorithm>
#include <cmath>

namespace masq {

namespace {

// The clipped box is computed in double; a relative pad of 1e-9 of the piece's extent
// and position absorbs its rounding. The fp32 outward rounding of the wide collapse
// comes on top.
Aabb finish(Aabb b, int axis, double lo, double hi) {
  if (b.empty()) return b;
  // The extent is at most twice the largest coordinate magnitude, so 2e-9 of that
  // covers both (and costs no more than a few comparisons: this runs per clip).
  double m = 0.0;
  for (int k = 0; k < 3; ++k) m = std::max(m, std::max(std::abs(b.lo[k]), std::abs(b.hi[k])));
  double pad = 2e-9 * m + 1e-300;
  b.lo -= glm::dvec3(pad);
  b.hi += glm::dvec3(pad);
  // The slab bounds themselves are exact cuts: the part inside cannot leave them.
  b.lo[axis] = std::max(b.lo[axis], lo);
  b.hi[axis] = std::min(b.hi[axis], hi);
  if (!(b.lo[axis] <= b.hi[axis])) return Aabb{};
  return b;
}

// Parameter range [t0, t1] of the segment a + t (b - a), t in [0, 1], whose axis
// coordinate lies in [lo, hi]; false when none.
bool segment_range(double a, double b, double lo, double hi, double& t0, double& t1) {
  double d = b - a;
  if (d == 0.0) {
    t0 = 0.0;
    t1 = 1.0;
    return a >= lo && a <= hi;
  }
  double s0 = (lo - a) / d, s1 = (hi - a) / d;
  if (s0 > s1) std::swap(s0, s1);
  t0 = std::max(0.0, s0);
  t1 = std::min(1.0, s1);
  return t0 <= t1;
}

} // namespace

Aabb clip_segment(const glm::dvec3& a, double ra, const glm::dvec3& b, double rb, int axis, double lo, double hi) {
  // A point of the hull of the two end balls lies within r(t) = lerp(ra, rb, t) of the
  // axis point s(t), so it can be in the slab only if s(t) is within max(ra, rb) of it.
  double rmax = std::max(ra, rb);
  double t0, t1;
  if (!segment_range(a[axis], b[axis], lo - rmax, hi + rmax, t0, t1)) return Aabb{};
  // Widen the range by a relative hair: the division above rounds.
  t0 = std::max(0.0, t0 - 1e-12);
  t1 = std::min(1.0, t1 + 1e-12);
  glm::dvec3 p0 = a + t0 * (b - a), p1 = a + t1 * (b - a);
  double r = std::max(ra + t0 * (rb - ra), ra + t1 * (rb - ra)); // r(t) is linear: its max on [t0,t1] is at an end
  Aabb box;
  box.grow(p0 - glm::dvec3(r));
  box.grow(p0 + glm::dvec3(r));
  box.grow(p1 - glm::dvec3(r));
  box.grow(p1 + glm::dvec3(r));
  return finish(box, axis, lo, hi);
}

Aabb clip_sphere(const glm::dvec3& c, double r, int axis, double lo, double hi) {
  Aabb box;
  box.grow(c - glm::dvec3(r));
  box.grow(c + glm::dvec3(r));
  if (box.hi[axis] < lo || box.lo[axis] > hi) return Aabb{};
  return finish(box, axis, lo, hi);
}

Aabb clip_triangle(const std::array<glm::dvec3, 3>& v, int axis, double lo, double hi) {
  // Sutherland-Hodgman against the two planes; the polygon inside is convex with at
  // most five vertices (fixed arrays: this runs for every straddling triangle in every
  // spatial bin, and heap vectors made SBVH builds several times slower).
  std::array<glm::dvec3, 8> poly{v[0], v[1], v[2]}, next{};
  int n = 3;
  auto clip_plane = [&](double plane, bool keep_above) {
    int m = 0;
    for (int i = 0; i < n; ++i) {
      const glm::dvec3& p = poly[std::size_t(i)];
      const glm::dvec3& q = poly[std::size_t((i + 1) % n)];
      double dp = keep_above ? p[axis] - plane : plane - p[axis];
      double dq = keep_above ? q[axis] - plane : plane - q[axis];
      if (dp >= 0) next[std::size_t(m++)] = p;
      if ((dp < 0 && dq > 0) || (dp > 0 && dq < 0)) {
        glm::dvec3 x = p + (dp / (dp - dq)) * (q - p);
        x[axis] = plane; // on the plane exactly; the other coordinates carry the rounding
        next[std::size_t(m++)] = x;
      }
    }
    poly = next;
    n = m;
  };
  clip_plane(lo, true);
  if (n > 0) clip_plane(hi, false);
  Aabb box;
  for (int i = 0; i < n; ++i) box.grow(poly[std::size_t(i)]);
  return finish(box, axis, lo, hi);
}

namespace {

// Bezier clipping along one coordinate: the parameter range where the control
// polygon's convex hull (in the (t, y) plane, control points at t = i/3) meets the band
// [lo, hi] contains every t where the curve does. The extremes of hull-and-band are
// control points inside the band or crossings of hull edges with the band lines, and
// every pairwise segment of the control points lies in the hull, so testing all six
// pairs finds them.
bool hull_band_range(const std::array<double, 4>& y, double lo, double hi, double& t0, double& t1) {
  t0 = INFINITY;
  t1 = -INFINITY;
  auto take = [&](double t) {
    t0 = std::min(t0, t);
    t1 = std::max(t1, t);
  };
  for (int i = 0; i < 4; ++i)
    if (y[i] >= lo && y[i] <= hi) take(i / 3.0);
  for (int i = 0; i < 4; ++i)
    for (int j = i + 1; j < 4; ++j)
      for (double line : {lo, hi}) {
        double di = y[i] - line, dj = y[j] - line;
        if ((di < 0 && dj > 0) || (di > 0 && dj < 0)) {
          double s = di / (di - dj);
          take((i + s * (j - i)) / 3.0);
        }
      }
  if (!(t0 <= t1)) return false;
  t0 = std::max(0.0, t0 - 1e-12);
  t1 = std::min(1.0, t1 + 1e-12);
  return true;
}

// Control points of the piece [t0, t1] of a cubic (two de Casteljau splits).
std::array<glm::dvec3, 4> sub_curve(const std::array<glm::dvec3, 4>& p, double t0, double t1) {
  auto split_right = [](const std::array<glm::dvec3, 4>& c, double t) { // the part [t, 1]
    glm::dvec3 a = glm::mix(c[0], c[1], t), b = glm::mix(c[1], c[2], t), d = glm::mix(c[2], c[3], t);
    glm::dvec3 ab = glm::mix(a, b, t), bd = glm::mix(b, d, t);
    return std::array<glm::dvec3, 4>{glm::mix(ab, bd, t), bd, d, c[3]};
  };
  auto split_left = [](const std::array<glm::dvec3, 4>& c, double t) { // the part [0, t]
    glm::dvec3 a = glm::mix(c[0], c[1], t), b = glm::mix(c[1], c[2], t), d = glm::mix(c[2], c[3], t);
    glm::dvec3 ab = glm::mix(a, b, t), bd = glm::mix(b, d, t);
    return std::array<glm::dvec3, 4>{c[0], a, ab, glm::mix(ab, bd, t)};
  };
  std::array<glm::dvec3, 4> right = t0 > 0.0 ? split_right(p, t0) : p;
  if (t1 >= 1.0) return right;
  double s = (t1 - t0) / (1.0 - t0); // t1 in the parameter of [t0, 1]
  return split_left(right, std::min(1.0, s));
}

} // namespace

Aabb clip_curve(const std::array<glm::dvec3, 4>& p, double radius, int axis, double lo, double hi) {
  // The swept ball of radius r at B(t) can reach the slab only if B(t)[axis] lies in
  // [lo - r, hi + r]. Three rounds of Bezier clipping tighten the parameter range (each
  // works on the previous piece, whose hull is tighter); the piece's control points,
  // inflated by r, bound the tube over it.
  std::array<glm::dvec3, 4> piece = p;
  for (int round = 0; round < 3; ++round) {
    std::array<double, 4> y{piece[0][axis], piece[1][axis], piece[2][axis], piece[3][axis]};
    double t0, t1;
    if (!hull_band_range(y, lo - radius, hi + radius, t0, t1)) return Aabb{};
    if (t0 <= 0.0 && t1 >= 1.0) break;
    piece = sub_curve(piece, t0, t1);
  }
  // The de Casteljau points carry rounding of the order of 1e-16 of their magnitude;
  // finish() pads far more than that.
  Aabb box;
  for (const glm::dvec3& c : piece) {
    box.grow(c - glm::dvec3(radius));
    box.grow(c + glm::dvec3(radius));
  }
  return finish(box, axis, lo, hi);
}

Aabb clip_primitive(const Geometry& g, std::size_t prim, int axis, double lo, double hi) {
  const ScenePrimRow& row = scene_prim_row(g.type);
  PrimBalls b;
  row.balls(g, prim, b);
  auto d = [&](int i) { return glm::dvec3(b[std::size_t(i)].centre); };
  switch (row.shape) {
    case PrimShape::Triangle: return clip_triangle({d(0), d(1), d(2)}, axis, lo, hi);
    case PrimShape::Segment: return clip_segment(d(0), b[0].radius, d(1), b[1].radius, axis, lo, hi);
    case PrimShape::Ball: return clip_sphere(d(0), b[0].radius, axis, lo, hi);
    case PrimShape::Bezier: return clip_curve({d(0), d(1), d(2), d(3)}, b[0].radius, axis, lo, hi);
  }
  throw Error("clip: unknown primitive shape");
}

} // namespace masq
