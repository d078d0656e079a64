// Axis-aligned box in double precision (builds are done in double and rounded outward
// to fp32 only when packed for the GPU).
#pragma once
#include <glm/glm.hpp>
#include <limits>

namespace masq {

struct Aabb {
  glm::dvec3 lo{std::numeric_limits<double>::infinity()};
  glm::dvec3 hi{-std::numeric_limits<double>::infinity()};

  bool empty() const { return !(lo.x <= hi.x && lo.y <= hi.y && lo.z <= hi.z); }
  void grow(const glm::dvec3& p) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  void grow(const Aabb& b) {
    lo = glm::min(lo, b.lo);
    hi = glm::max(hi, b.hi);
  }
  glm::dvec3 center() const { return 0.5 * (lo + hi); }
  double area() const {
    if (empty()) return 0.0;
    glm::dvec3 e = hi - lo;
    return 2.0 * (e.x * e.y + e.y * e.z + e.z * e.x);
  }
  static Aabb intersect(const Aabb& a, const Aabb& b) {
    Aabb r;
    r.lo = glm::max(a.lo, b.lo);
    r.hi = glm::min(a.hi, b.hi);
    return r;
  }
};

// fp32 bounds that contain the double value (rounded toward -inf / +inf).
float round_down(double x);
float round_up(double x);

} // namespace masq
