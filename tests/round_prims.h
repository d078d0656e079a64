// The round primitives under test (capsule, round cone, sphere) in fp32: their robust
// and fast kernels and the oracle on the same shape, their exact geometry and surface
// sampling, and silhouette and random rays against one of them at a configured size,
// length, distance and translation (test_intersectors_round.cpp).
#pragma once
#include "kernels/intersect_capsule.h"
#include "kernels/intersect_capsule_fast.h"
#include "kernels/intersect_round_cone.h"
#include "kernels/intersect_sphere.h"
#include "tests/intersector_compare.h"
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

namespace masq::test {

namespace K = masq::kernel;

enum class Kind { Capsule, Cone, Sphere };
inline const char* kind_name(Kind k) { return k == Kind::Capsule ? "capsule" : (k == Kind::Cone ? "cone" : "sphere"); }

// One capsule (ra = rb), round cone, or sphere (a = b, ra = rb) in fp32.
struct Round {
  Kind kind;
  glm::vec3 a, b;
  float ra, rb;
};

inline KV::PrimHit run_kernel(const Round& p, bool fast, glm::vec3 o, glm::vec3 d, float tmin = 0, float tmax = kInfF) {
  if (p.kind == Kind::Capsule) {
    K::Capsule c{{p.a.x, p.a.y, p.a.z}, p.ra, {p.b.x, p.b.y, p.b.z}, 0};
    return fast ? KV::intersect_capsule_fast(c, o, d, tmin, tmax) : KV::intersect_capsule(c, o, d, tmin, tmax);
  }
  if (p.kind == Kind::Cone) {
    K::RoundCone c{{p.a.x, p.a.y, p.a.z}, p.ra, {p.b.x, p.b.y, p.b.z}, p.rb};
    return fast ? KV::intersect_round_cone_fast(c, o, d, tmin, tmax)
                : KV::intersect_round_cone(c, o, d, tmin, tmax);
  }
  K::Sphere s{{p.a.x, p.a.y, p.a.z}, p.ra};
  return fast ? KV::intersect_sphere_fast(s, o, d, tmin, tmax) : KV::intersect_sphere(s, o, d, tmin, tmax);
}

inline PrimResult run_oracle(const Round& p, const PrimRay& ray) {
  if (p.kind == Kind::Capsule) {
    masq::CapsulePrim c;
    c.a = p.a;
    c.b = p.b;
    c.radius = p.ra;
    return masq::oracle::oracle_capsule(c, ray);
  }
  if (p.kind == Kind::Cone) {
    masq::RoundConePrim c;
    c.a = p.a;
    c.ra = p.ra;
    c.b = p.b;
    c.rb = p.rb;
    return masq::oracle::oracle_round_cone(c, ray);
  }
  masq::SpherePrim s;
  s.center = p.a;
  s.radius = p.ra;
  return masq::oracle::oracle_sphere(s, ray);
}

// The exact geometry of a (rounded) primitive, for sampling its surface.
struct Geo {
  Vld a, b, c, w;
  ld ra, rb, len, sn, cs;
  bool ball; // one sphere contains the other (or zero length)
};
inline Geo geometry(const Round& p) {
  Geo g;
  g.a = to_ld(p.a);
  g.b = to_ld(p.b);
  g.c = 0.5L * (g.a + g.b);
  g.ra = std::max<ld>(p.ra, 0);
  g.rb = std::max<ld>(p.rb, 0);
  g.len = lenl(g.b - g.a);
  g.ball = !(g.len > std::fabs(g.ra - g.rb));
  g.w = g.len > 0 ? (1 / g.len) * (g.b - g.a) : Vld{0, 0, 1};
  g.sn = g.ball ? 0 : (g.ra - g.rb) / g.len;
  g.cs = std::sqrt((1 - g.sn) * (1 + g.sn));
  return g;
}
inline ld rmax(const Geo& g) { return std::max(g.ra, g.rb); }
inline ld rmin(const Geo& g) { return g.ball ? rmax(g) : std::min(g.ra, g.rb); }

struct SurfPt {
  Vld p, n; // point, outward unit normal
  ld rloc;  // local radius (for offsets)
};

// A random surface point: the lateral surface (60%) or an exposed sphere part.
inline SurfPt sample_surface(const Geo& g, Rng& rng) {
  if (g.ball) {
    bool big_a = g.ra >= g.rb;
    Vld n = rand_unit(rng);
    ld r = big_a ? g.ra : g.rb;
    return {(big_a ? g.a : g.b) + r * n, n, r};
  }
  for (int tries = 0; tries < 100; ++tries) {
    ld pick = uni(rng, 0, 1);
    if (pick < 0.6) {
      ld za = g.ra * g.sn, zb = g.len + g.rb * g.sn;
      ld z = uni(rng, za, zb);
      Vld e = rand_perp(rng, g.w);
      ld rho = (g.ra - z * g.sn) / g.cs;
      return {g.a + z * g.w + rho * e, g.cs * e + g.sn * g.w, std::max(rho, g.rb)};
    }
    bool on_a = pick < 0.8;
    ld r = on_a ? g.ra : g.rb;
    if (!(r > 0)) continue;
    Vld n = rand_unit(rng);
    ld nw = dotl(n, g.w);
    if (on_a ? nw <= g.sn : nw >= g.sn) return {(on_a ? g.a : g.b) + r * n, n, r};
  }
  return {g.a + g.ra * rand_perp(rng, g.w), rand_perp(rng, g.w), g.ra};
}

inline Scale round_scale(const Geo& g) { return {g.c, g.len, rmax(g), rmin(g), g.ball ? 0 : g.len}; }

struct Config {
  Kind kind;
  ld r;         // radius (cone: the bigger one)
  ld len_r;     // length / r
  ld dist_r;    // distance of ray origins / r
  ld translate; // the whole scene moved by (T, T, T)
};

inline Round make_round(const Config& cf, Rng& rng) {
  Vld c = Vld{uni(rng, -1, 1), uni(rng, -1, 1), uni(rng, -1, 1)} + Vld{cf.translate, cf.translate, cf.translate};
  Vld w = rand_unit(rng);
  ld half = cf.kind == Kind::Sphere ? 0 : 0.5L * cf.len_r * cf.r;
  Round p{cf.kind, to_f(c - half * w), to_f(c + half * w), float(cf.r), float(cf.r)};
  if (cf.kind == Kind::Cone) {
    float small = float(cf.r * uni(rng, 0.1, 0.9));
    (uni(rng, 0, 1) < 0.5 ? p.ra : p.rb) = small;
  }
  return p;
}

struct Result {
  Tally robust_sil, robust_rand, fast_sil, fast_rand;
  void add(const Result& o) {
    robust_sil.add(o.robust_sil);
    robust_rand.add(o.robust_rand);
    fast_sil.add(o.fast_sil);
    fast_rand.add(o.fast_rand);
  }
};

// Silhouette rays (tangent to the surface, passing at (1e-3..1e-1) * local radius
// outside or inside it) and random rays aimed at the primitive's neighbourhood, from
// distance dist_r * r, against one primitive.
inline Result run_prim(const Round& p, ld dist_r, int n_sil, int n_rand, Rng& rng) {
  Result res;
  Geo g = geometry(p);
  Scale sc = round_scale(g);
  ld r = rmax(g);
  ld dist = dist_r * r;
  for (int i = 0; i < n_sil + n_rand; ++i) {
    bool sil = i < n_sil;
    Vld o, aim;
    if (sil) {
      SurfPt s = sample_surface(g, rng);
      ld delta = log_uni(rng, 1e-3, 1e-1) * (uni(rng, 0, 1) < 0.5 ? -1 : 1);
      aim = s.p + (delta * s.rloc) * s.n;
      o = aim - dist * rand_perp(rng, s.n);
    } else {
      aim = g.a + uni(rng, 0, 1) * (g.b - g.a) + (2 * r * std::cbrt(uni(rng, 0, 1))) * rand_unit(rng);
      o = g.c + dist * rand_unit(rng);
    }
    auto [of, df] = aimed_ray(o, aim, rng);
    PrimRay ray = ld_ray(of, df);
    PrimResult ref = run_oracle(p, ray);
    compare(run_kernel(p, false, of, df), ref, ray, sc, sil ? res.robust_sil : res.robust_rand);
    compare(run_kernel(p, true, of, df), ref, ray, sc, sil ? res.fast_sil : res.fast_rand);
  }
  return res;
}

// At T = 1e5 the fp32 spacing is 2^-7 = 78 r: end points closer than that collapse, so
// the short rows there are zero-length primitives (spheres), long ones are re-rounded.
inline std::vector<Config> configs(Kind kind) {
  std::vector<Config> out;
  std::vector<ld> lens = kind == Kind::Sphere ? std::vector<ld>{0} : std::vector<ld>{1, 1e2, 1e4};
  if (kind == Kind::Capsule) lens.insert(lens.begin(), 0);
  for (ld T : {0.0L, 1e5L})
    for (ld lr : lens)
      for (ld dr : {1e1L, 1e2L, 1e3L, 1e4L, 1e5L, 1e6L}) out.push_back({kind, 1e-4L, lr, dr, T});
  return out;
}

inline void print_header() {
  std::printf("kind     transl    L/r    D/r |  rays   band | robust: sil   sil-raw  rand    | max dt/r n-err   | "
              "fast (as written): sil-raw  sil  rand-raw\n");
}
inline void print_row(const char* kind, ld T, ld lr, ld dr, const Result& r) {
  std::printf("%-7s %7.0Lg %6.0Lg %6.0Lg | %6ld %5.1f%% | %.1e %.1e %.1e | %.1e %.1e | %6.2f%% %6.2f%% %6.2f%%\n", kind, T,
              lr, dr, r.robust_sil.n, 100 * r.robust_sil.amb_rate(), r.robust_sil.rate(), r.robust_sil.rate_raw(),
              r.robust_rand.rate(), double(r.robust_sil.max_dt), double(r.robust_sil.max_nerr),
              100 * r.fast_sil.rate_raw(), 100 * r.fast_sil.rate(), 100 * r.fast_rand.rate_raw());
}

} // namespace masq::test
