#include "bvh/bounds/bounding_sphere.h"
#include <algorithm>
#include <array>
#include <cmath>

namespace masq {

namespace {

bool contains(const Ball& b, const glm::dvec3& p) {
  // Relative slack: the support points were chosen by the same double arithmetic.
  return b.radius >= 0 && glm::length(p - b.centre) <= b.radius * (1.0 + 1e-12) + 1e-300;
}

Ball ball_of(const glm::dvec3& a) { return {a, 0.0}; }

Ball ball_of(const glm::dvec3& a, const glm::dvec3& b) {
  glm::dvec3 c = 0.5 * (a + b);
  return {c, 0.5 * glm::length(b - a)};
}

// Circumball of a triangle (smallest ball with all three on its boundary, in their plane).
Ball ball_of(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) {
  glm::dvec3 ab = b - a, ac = c - a;
  glm::dvec3 n = glm::cross(ab, ac);
  double den = 2.0 * glm::dot(n, n);
  if (!(den > 0)) { // collinear: the ball of the farthest pair
    Ball best = ball_of(a, b);
    for (Ball x : {ball_of(a, c), ball_of(b, c)})
      if (x.radius > best.radius) best = x;
    return best;
  }
  glm::dvec3 off = (glm::dot(ac, ac) * glm::cross(n, ab) + glm::dot(ab, ab) * glm::cross(ac, n)) / den;
  return {a + off, glm::length(off)};
}

// Circumball of a tetrahedron.
Ball ball_of(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, const glm::dvec3& d) {
  glm::dvec3 ab = b - a, ac = c - a, ad = d - a;
  double det = glm::dot(ab, glm::cross(ac, ad));
  if (!(std::fabs(det) > 0)) { // coplanar: the best of the faces that covers all four
    Ball best{{0, 0, 0}, INFINITY};
    const std::array<glm::dvec3, 4> p = {a, b, c, d};
    for (int skip = 0; skip < 4; ++skip) {
      std::array<glm::dvec3, 3> t;
      for (int i = 0, k = 0; i < 4; ++i)
        if (i != skip) t[k++] = p[i];
      Ball x = ball_of(t[0], t[1], t[2]);
      if (contains(x, p[skip]) && x.radius < best.radius) best = x;
    }
    return best;
  }
  glm::dvec3 off = (glm::dot(ab, ab) * glm::cross(ac, ad) + glm::dot(ac, ac) * glm::cross(ad, ab) +
                    glm::dot(ad, ad) * glm::cross(ab, ac)) /
                   (2.0 * det);
  return {a + off, glm::length(off)};
}

Ball ball_of_support(const std::vector<glm::dvec3>& r) {
  switch (r.size()) {
    case 0: return {};
    case 1: return ball_of(r[0]);
    case 2: return ball_of(r[0], r[1]);
    case 3: return ball_of(r[0], r[1], r[2]);
    default: return ball_of(r[0], r[1], r[2], r[3]);
  }
}

Ball welzl(std::vector<glm::dvec3>& p, std::size_t n, std::vector<glm::dvec3>& support) {
  Ball b = ball_of_support(support);
  if (support.size() == 4) return b;
  for (std::size_t i = 0; i < n; ++i) {
    if (contains(b, p[i])) continue;
    support.push_back(p[i]);
    b = welzl(p, i, support);
    support.pop_back();
    // Move to front: points that forced a new ball are tried first next time.
    std::rotate(p.begin(), p.begin() + std::ptrdiff_t(i), p.begin() + std::ptrdiff_t(i) + 1);
  }
  return b;
}

// EPOS-26's 13 directions: the 3 axes, the 4 cube diagonals, the 6 edge diagonals.
const std::array<glm::dvec3, 13> kSphereDirs = {
    glm::dvec3{1, 0, 0},  {0, 1, 0},  {0, 0, 1},  {1, 1, 1}, {1, 1, -1}, {1, -1, 1}, {1, -1, -1},
    {1, 1, 0},  {1, -1, 0}, {1, 0, 1}, {1, 0, -1}, {0, 1, 1}, {0, 1, -1}};

} // namespace

Ball min_ball(std::span<const glm::dvec3> points) {
  std::vector<glm::dvec3> p(points.begin(), points.end());
  std::vector<glm::dvec3> support;
  return welzl(p, p.size(), support);
}

Ball epos26_ball(std::span<const BallHull> hulls) {
  // Extremal ball centres along each direction, by the balls' support (radius included).
  std::vector<glm::dvec3> extremes;
  for (const glm::dvec3& d : kSphereDirs) {
    double lo = INFINITY, hi = -INFINITY;
    glm::dvec3 plo{0.0}, phi{0.0};
    double len = glm::length(d);
    for (const BallHull& h : hulls)
      for (int i = 0; i < h.count; ++i) {
        double s = glm::dot(d, h.centre[i]);
        if (s - h.radius[i] * len < lo) lo = s - h.radius[i] * len, plo = h.centre[i];
        if (s + h.radius[i] * len > hi) hi = s + h.radius[i] * len, phi = h.centre[i];
      }
    if (lo <= hi) {
      extremes.push_back(plo);
      extremes.push_back(phi);
    }
  }
  if (extremes.empty()) return {};
  Ball b = min_ball(extremes);
  // Grow (Ritter): the smallest ball holding the current one and the ball (c, r).
  for (const BallHull& h : hulls)
    for (int i = 0; i < h.count; ++i) {
      glm::dvec3 v = h.centre[i] - b.centre;
      double d = glm::length(v);
      double need = d + h.radius[i];
      if (need <= b.radius) continue;
      if (h.radius[i] >= d + b.radius || !(d > 0)) { // the new ball holds the old one
        b = {h.centre[i], std::max(h.radius[i], need)};
        continue;
      }
      double nr = 0.5 * (b.radius + need);
      b.centre += v * ((nr - b.radius) / d);
      b.radius = nr;
    }
  // The growth steps round: make the radius exact for the final centre.
  double r = 0;
  for (const BallHull& h : hulls)
    for (int i = 0; i < h.count; ++i) r = std::max(r, glm::length(h.centre[i] - b.centre) + h.radius[i]);
  b.radius = r;
  return b;
}

} // namespace masq
