// The comparison of an fp32 intersector's answer with the oracle's, for the round
// primitives and triangles (test_intersectors_round.cpp, test_intersectors_triangle.cpp).
//
// What may legitimately disagree (the "band"). Inputs are fp32 and the oracle is exact
// on them, but no fp32 intersector can place the ray's closest approach to the
// primitive better than about u (|o - c| + L) (u = 2^-24): o - a rounds by u |o - a|,
// the ray point o + t d at distance |o - c| rounds by as much (without an extended-
// precision multiply-add), the projections onto the axis by u L. So a ray whose oracle
// clearance (|distance - r| / r; triangles: smallest barycentric) is below
//   band = 1e-4 + kBand u (|o - c| + L) / r        (triangles: r = smallest height * cos i)
// may flip between hit and miss in any fp32 implementation; such flips are counted and
// printed, not held against the robust variants. kBand = 4 bounds the two roundings of
// a 3-vector of that size (2 sqrt(3) u); the flips measured lie within 1.2 u of the
// floor. 1e-4 covers the intersector's own O(100 u) arithmetic. Outside the band the
// robust variants must agree on hit/miss (rate < 1e-4), on t within
// (1e-3 r + kBand u (|o - c| + L)) / cos(i) (a lateral error becomes an error along the
// ray divided by the cosine of the incidence angle), and on the normal and u likewise.
#pragma once
#include "kernels/prim_hit.h"
#include "tests/intersector_util.h"
#include <algorithm>
#include <cmath>
#include <cstdio>

namespace masq::test {

namespace KV = masq::kernel::v_default;

struct Tally {
  long n = 0, amb = 0, flips = 0, flips_raw = 0, both = 0, t_bad = 0, n_bad = 0, u_bad = 0;
  ld max_dt = 0;   // max |dt| |d| cos(i) / r over common hits outside the band
  ld max_nerr = 0; // max normal angle (radians) over those with cos(i) > 0.1
  ld k_needed = 0; // max over raw flips of (clearance - kBandFloor) r / (u (|o - c| + L))
  void add(const Tally& o) {
    n += o.n;
    amb += o.amb;
    flips += o.flips;
    flips_raw += o.flips_raw;
    both += o.both;
    t_bad += o.t_bad;
    n_bad += o.n_bad;
    u_bad += o.u_bad;
    max_dt = std::max(max_dt, o.max_dt);
    max_nerr = std::max(max_nerr, o.max_nerr);
    k_needed = std::max(k_needed, o.k_needed);
  }
  double rate() const { return n > 0 ? double(flips) / double(n) : 0; }
  double rate_raw() const { return n > 0 ? double(flips_raw) / double(n) : 0; }
  double amb_rate() const { return n > 0 ? double(amb) / double(n) : 0; }
};

// The scales of one primitive the tolerances are made of.
struct Scale {
  Vld centre; // o - centre enters the band
  ld len;     // length (enters the band; 0 for spheres and triangles)
  ld r;       // size the clearance is relative to (capsule/cone/sphere: max radius)
  ld rmin;    // smallest curvature radius (normal tolerance)
  ld ulen;    // length u (and v) are relative to; 0: not checked
};

// Compares one kernel answer with the oracle's.
inline void compare(const KV::PrimHit& h, const PrimResult& ref, const PrimRay& ray, const Scale& sc, Tally& tl) {
  ++tl.n;
  ld dl = lenl(ray.d);
  ld slack = kBand * kU * (lenl(ray.o - sc.centre) + sc.len); // distance units
  bool amb = ref.clearance < kBandFloor + slack / sc.r;
  if (amb) ++tl.amb;
  bool kh = h.hit != 0;
  if (kh != ref.hit) {
    ++tl.flips_raw;
    if (!amb) ++tl.flips;
    tl.k_needed = std::max(tl.k_needed, (ref.clearance - kBandFloor) * sc.r / (slack / kBand));
    return;
  }
  if (!kh || amb) return;
  ++tl.both;
  ld tol = kTolRel * sc.r + slack; // lateral position, distance units
  ld cosi = std::fabs(dotl(ref.normal, ray.d)) / dl;
  ld cosc = std::max<ld>(cosi, 1e-3L);
  ld err = std::fabs(ld(h.t) - ref.t) * dl * cosi;
  if (err > tol) ++tl.t_bad;
  tl.max_dt = std::max(tl.max_dt, err / sc.r);
  // Normal: a lateral error e moves the hit by e / cos(i) along a surface whose
  // curvature radius is at least rmin, turning the normal by about e / (rmin cos(i)).
  Vld nk = to_ld(glm::vec3(h.normal.x, h.normal.y, h.normal.z));
  ld ang = lenl(nk) > 0 ? std::acos(std::clamp<ld>(dotl(unitl(nk), ref.normal), -1, 1)) : ld(M_PI);
  // (Flat primitives, rmin = inf: the normal is a cross product of edges, exact to u.)
  ld tol_n = std::isinf(sc.rmin) ? 1e-5L : 2 * tol / (sc.rmin * cosc);
  if (ang > tol_n) ++tl.n_bad;
  if (cosi > 0.1L) tl.max_nerr = std::max(tl.max_nerr, ang);
  // u (and v): the hit moves by up to e / cos(i).
  if (sc.ulen > 0) {
    ld tol_u = 2 * tol / (cosc * sc.ulen) + 1e-6L;
    if (std::fabs(ld(h.u) - ref.u) > tol_u || std::fabs(ld(h.v) - ref.v) > tol_u) ++tl.u_bad;
  }
}

inline void expect_robust(const Tally& t, const char* what) {
  std::printf("%s: robust %ld rays, %ld flips outside the band (rate %.2e), %ld raw flips (%.2e); of %ld common hits "
              "%ld t, %ld normals, %ld u/v outside tolerance; max |dt| cos(i)/r %.2e; flips lie within %.2f u (|o-c|+L) "
              "of the band floor (band: %.0f)\n",
              what, t.n, t.flips, t.rate(), t.flips_raw, t.rate_raw(), t.both, t.t_bad, t.n_bad, t.u_bad,
              double(t.max_dt), double(t.k_needed), double(kBand));
  EXPECT_LT(t.rate(), 1e-4) << what << ": robust hit/miss disagreements outside the band";
  EXPECT_LT(double(t.t_bad), 1e-4 * double(t.both) + 0.5) << what << ": t";
  EXPECT_LT(double(t.n_bad), 1e-4 * double(t.both) + 0.5) << what << ": normals";
  EXPECT_LT(double(t.u_bad), 1e-4 * double(t.both) + 0.5) << what << ": u/v";
}

} // namespace masq::test
