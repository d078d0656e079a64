// What the per-primitive oracle files (oracle_<type>.cpp) share: long-double vector
// arithmetic, the ray's validity and self window, boundary crossings and their
// selection, the ray re-based near a primitive, the sphere's crossings and the
// clearance of solids swept along a segment. Internal to oracle/: the tests use their
// own arithmetic, so an error here cannot cancel in both.
//
// Conventions every primitive follows:
//  - Every quadratic is solved with the ray re-based near the primitive (spheres: the
//    closest approach to the centre; capsule and cone: to the axis, within the solid's
//    axial extent), so its terms live on the primitive's scale rather than the distance
//    travelled or the length, and with the cancellation-free root pair (solve.h).
//  - Clearance of spheres, capsules and round cones is the exact gap between the ray segment
//    and the solid (closed form, see linear_core_gap); curves: see oracle_curve.
//  - Convex solids (sphere, capsule, cone): the ray meets the boundary at its entry and
//    exit, so the crossing interval is [min, max] of the boundary crossings found
//    (pieces meet at seams; a seam tolerance of 1e-12 of the size keeps both pieces'
//    crossings there, which deviate from the true surface only to second order).
#pragma once
#include "oracle/oracle_prims.h"
#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

namespace masq::oracle::detail {

inline const ld kInf = std::numeric_limits<ld>::infinity();
inline constexpr ld kSeam = 1e-12L;

inline Vld operator+(Vld a, Vld b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
inline Vld operator-(Vld a, Vld b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
inline Vld operator*(ld s, Vld a) { return {s * a.x, s * a.y, s * a.z}; }
inline ld dot(Vld a, Vld b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline Vld cross(Vld a, Vld b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
inline ld len(Vld a) { return std::sqrt(dot(a, a)); }
inline Vld unit(Vld a) {
  ld l = len(a);
  return l > 0 ? (1 / l) * a : Vld{};
}
inline Vld from(const glm::vec3& v) { return {v.x, v.y, v.z}; }
inline bool finite(Vld a) { return std::isfinite(a.x) && std::isfinite(a.y) && std::isfinite(a.z); }
inline ld nonneg(float r) { return r > 0 ? ld(r) : 0; } // negative and NaN radii: no surface
inline ld clamp01(ld x) { return std::clamp<ld>(x, 0, 1); }

// False for the rays oracle_prims.h calls invalid (NaN/Inf in o or d, d = 0, NaN
// limits, tmin > tmax).
bool valid(const PrimRay& r);

// The lower end of the window crossings are taken from: tmin or the self window.
ld window_lo(const PrimRay& ray, ld r, Vld centre, ld span = 0);

// Clearance first: it is the exact gap between the ray segment and the solid, so a
// clearly positive gap means no crossing in [tmin, tmax] and the crossing solve is
// skipped (most primitive/ray pairs of a brute-force scene trace).
bool gap_clear(ld gap, ld r);

// A boundary crossing: ray parameter, outward normal (any length), axial/curve parameter.
struct Bound {
  ld t;
  Vld n;
  ld u;
};

// The first of the ascending crossings b[0..n) in [lo, tmax] is the hit.
void select(const Bound* b, int n, ld lo, ld tmax, PrimResult& res);

// Crossings of a convex solid: the nearest and farthest are its entry and exit.
struct Hull {
  bool any = false;
  Bound in{kInf, {}, 0}, out{-kInf, {}, 0};
  void add(ld t, Vld n, ld u) {
    if (!std::isfinite(t)) return;
    any = true;
    if (t < in.t) in = {t, n, u};
    if (t > out.t) out = {t, n, u};
  }
};

void select_hull(const Hull& h, const PrimRay& ray, ld r, Vld centre, ld span, PrimResult& res);

// The ray re-based at its closest approach to c: point o + t0 d, parameter tau = t - t0.
struct Based {
  Vld o;
  ld t0;
};
Based base_at(Vld o, Vld d, Vld c);

// For a solid of revolution about the axis a + y w (|w| = 1) spanning y in [ylo, yhi]:
// the ray re-based at its closest approach to the axis line, kept inside that slab.
// Based at the centre alone, a ray meeting a long thin solid near one end would solve a
// quadratic whose terms are (L / r)^2 larger than their difference.
Based base_at_axis(Vld o, Vld d, Vld a, Vld w, ld ylo, ld yhi);

// Ray parameters where o + t d crosses the sphere (c, r).
int sphere_roots(Vld c, ld r, Vld o, Vld d, ld out[2]);

// Crossings of the ball (c, r), each with parameter u (the sphere, and the round cone
// whose one ball contains the other).
Hull sphere_hull(Vld c, ld r, Vld o, Vld d, ld u);

// Clearance of a solid that is the union over s in [0,1] of the balls
// (a + s (b - a), ra + s (rb - ra)) (spheres, capsules, round cones):
//   G = min over s in [0,1], t in [tmin, tmax] of |o + t d - c(s)| - r(s),
// exactly the distance from the ray segment to the solid when the ray misses it
// (negative, a penetration depth, when it enters it). Returns {G, t at the minimiser}.
std::pair<ld, ld> linear_core_gap(Vld a, ld ra, Vld b, ld rb, const PrimRay& ray);

} // namespace masq::oracle::detail
