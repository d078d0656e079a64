// Axis-aligned box in double precision (builds are done in double and rounded outward
// to fp32 only when packed for the GPU).
#pragma once
#include <glm/glm.hpp>
#include <bit>
#include <cstdint>
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

// fp32 bounds that contain the double value (rounded toward -inf / +inf): f, a float
// nearest to x, steps one float away from x when it lies on the wrong side of it, on its
// bits as nextafter would (inline: every node format's collapse rounds six coordinates of
// every child box, and the library call was a few percent of auto's build).
inline float round_down(double x) {
  const float f = static_cast<float>(x);
  if (!(double(f) > x)) return f;
  if (f == 0.0f) return -std::numeric_limits<float>::denorm_min();
  const std::uint32_t bits = std::bit_cast<std::uint32_t>(f);
  return std::bit_cast<float>(f > 0.0f ? bits - 1u : bits + 1u); // +inf steps to FLT_MAX
}
inline float round_up(double x) {
  const float f = static_cast<float>(x);
  if (!(double(f) < x)) return f;
  if (f == 0.0f) return std::numeric_limits<float>::denorm_min();
  const std::uint32_t bits = std::bit_cast<std::uint32_t>(f);
  return std::bit_cast<float>(f > 0.0f ? bits + 1u : bits - 1u); // -inf steps to -FLT_MAX
}

// round_down of four doubles at once, lane by lane the same bits, without a branch (the
// binned SAH rounds the corners of every reference, whose directions are a coin toss
// from one to the next: a branch a corner was a tenth of a cluster BLAS build, in
// mispredictions). GCC/Clang vector extensions.
typedef double RoundDouble4 __attribute__((vector_size(32)));
typedef float RoundFloat4 __attribute__((vector_size(16)));
inline RoundFloat4 round_down_lanes(RoundDouble4 x) {
  typedef std::int32_t Int4 __attribute__((vector_size(16)));
  const RoundFloat4 f = __builtin_convertvector(x, RoundFloat4);
  const Int4 above = __builtin_convertvector(__builtin_convertvector(f, RoundDouble4) > x, Int4);
  const Int4 bits = std::bit_cast<Int4>(f);
  const std::int32_t minus_zero = std::bit_cast<std::int32_t>(-0.0f);
  Int4 below = f == 0.0f ? Int4{minus_zero, minus_zero, minus_zero, minus_zero} : bits; // -0: then -denorm_min
  below += f > 0.0f ? Int4{-1, -1, -1, -1} : Int4{1, 1, 1, 1};
  return std::bit_cast<RoundFloat4>(above ? below : bits);
}

} // namespace masq
