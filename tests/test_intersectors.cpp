// Primitive intersectors (kernels/intersect_*.h, compiled as C++) against the
// independent long-double oracle (oracle/oracle_prims.h), one ray and one primitive at
// a time. Robust variants are asserted; fast variants (Quilez as written, textbook
// sphere, Moller-Trumbore) are measured and printed (they exist for speed comparisons),
// and asserted only where their digits suffice (close, short primitives).
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
#include "kernels/intersect_capsule.h"
#include "kernels/intersect_capsule_fast.h"
#include "kernels/intersect_round_cone.h"
#include "kernels/intersect_sphere.h"
#include "kernels/intersect_triangle.h"
#include "oracle/oracle_prims.h"
#include <gtest/gtest.h>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <vector>

namespace {

namespace K = masq::kernel;
namespace KV = masq::kernel::v_default;
using masq::oracle::ld;
using masq::oracle::PrimRay;
using masq::oracle::PrimResult;
using masq::oracle::Vld;
using Rng = std::mt19937_64;

constexpr ld kU = 1.0L / 16777216; // 2^-24
constexpr ld kBand = 4;
constexpr ld kBandFloor = 1e-4L;
constexpr ld kTolRel = 1e-3L;
const float kInfF = std::numeric_limits<float>::infinity();
const ld kInfL = std::numeric_limits<ld>::infinity();

Vld operator+(Vld a, Vld b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
Vld operator-(Vld a, Vld b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
Vld operator*(ld s, Vld a) { return {s * a.x, s * a.y, s * a.z}; }
ld dotl(Vld a, Vld b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
Vld crossl(Vld a, Vld b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
ld lenl(Vld a) { return std::sqrt(dotl(a, a)); }
Vld unitl(Vld a) { return (1 / lenl(a)) * a; }
Vld to_ld(glm::vec3 v) { return {v.x, v.y, v.z}; }
glm::vec3 to_f(Vld v) { return {float(v.x), float(v.y), float(v.z)}; }

ld uni(Rng& g, ld lo, ld hi) { return lo + (hi - lo) * std::uniform_real_distribution<double>(0, 1)(g); }
ld log_uni(Rng& g, ld lo, ld hi) { return std::exp(uni(g, std::log(lo), std::log(hi))); }
Vld rand_unit(Rng& g) {
  std::normal_distribution<double> n(0, 1);
  Vld v{n(g), n(g), n(g)};
  return unitl(v);
}
Vld rand_perp(Rng& g, Vld n) { return unitl(crossl(n, rand_unit(g))); }

// ---------------------------------------------------------------- round primitives

enum class Kind { Capsule, Cone, Sphere };
const char* kind_name(Kind k) { return k == Kind::Capsule ? "capsule" : (k == Kind::Cone ? "cone" : "sphere"); }

// One capsule (ra = rb), round cone, or sphere (a = b, ra = rb) in fp32.
struct Round {
  Kind kind;
  glm::vec3 a, b;
  float ra, rb;
};

KV::PrimHit run_kernel(const Round& p, bool fast, glm::vec3 o, glm::vec3 d, float tmin = 0, float tmax = kInfF) {
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

PrimResult run_oracle(const Round& p, const PrimRay& ray) {
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

PrimRay ld_ray(glm::vec3 o, glm::vec3 d, float tmin = 0, float tmax = kInfF) {
  return {to_ld(o), to_ld(d), ld(tmin), ld(tmax)};
}

// The exact geometry of a (rounded) primitive, for sampling its surface.
struct Geo {
  Vld a, b, c, w;
  ld ra, rb, len, sn, cs;
  bool ball; // one sphere contains the other (or zero length)
};
Geo geometry(const Round& p) {
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
ld rmax(const Geo& g) { return std::max(g.ra, g.rb); }
ld rmin(const Geo& g) { return g.ball ? rmax(g) : std::min(g.ra, g.rb); }

struct SurfPt {
  Vld p, n; // point, outward unit normal
  ld rloc;  // local radius (for offsets)
};

// A random surface point: the lateral surface (60%) or an exposed sphere part.
SurfPt sample_surface(const Geo& g, Rng& rng) {
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

// ---------------------------------------------------------------- comparison

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
void compare(const KV::PrimHit& h, const PrimResult& ref, const PrimRay& ray, const Scale& sc, Tally& tl) {
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

Scale round_scale(const Geo& g) { return {g.c, g.len, rmax(g), rmin(g), g.ball ? 0 : g.len}; }

// ---------------------------------------------------------------- round primitives vs oracle

struct Config {
  Kind kind;
  ld r;         // radius (cone: the bigger one)
  ld len_r;     // length / r
  ld dist_r;    // distance of ray origins / r
  ld translate; // the whole scene moved by (T, T, T)
};

Round make_round(const Config& cf, Rng& rng) {
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

// A ray from the fp32 origin o towards aim, with a random non-unit length of d
// (computed from the rounded origin, so the ray really passes through aim).
std::pair<glm::vec3, glm::vec3> aimed_ray(Vld o, Vld aim, Rng& rng) {
  glm::vec3 of = to_f(o);
  Vld dir = aim - to_ld(of);
  ld scale = log_uni(rng, 1e-2, 1e2) / lenl(dir);
  return {of, to_f(scale * dir)};
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
Result run_prim(const Round& p, ld dist_r, int n_sil, int n_rand, Rng& rng) {
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
std::vector<Config> configs(Kind kind) {
  std::vector<Config> out;
  std::vector<ld> lens = kind == Kind::Sphere ? std::vector<ld>{0} : std::vector<ld>{1, 1e2, 1e4};
  if (kind == Kind::Capsule) lens.insert(lens.begin(), 0);
  for (ld T : {0.0L, 1e5L})
    for (ld lr : lens)
      for (ld dr : {1e1L, 1e2L, 1e3L, 1e4L, 1e5L, 1e6L}) out.push_back({kind, 1e-4L, lr, dr, T});
  return out;
}

void print_header() {
  std::printf("kind     transl    L/r    D/r |  rays   band | robust: sil   sil-raw  rand    | max dt/r n-err   | "
              "fast (as written): sil-raw  sil  rand-raw\n");
}
void print_row(const char* kind, ld T, ld lr, ld dr, const Result& r) {
  std::printf("%-7s %7.0Lg %6.0Lg %6.0Lg | %6ld %5.1f%% | %.1e %.1e %.1e | %.1e %.1e | %6.2f%% %6.2f%% %6.2f%%\n", kind, T,
              lr, dr, r.robust_sil.n, 100 * r.robust_sil.amb_rate(), r.robust_sil.rate(), r.robust_sil.rate_raw(),
              r.robust_rand.rate(), double(r.robust_sil.max_dt), double(r.robust_sil.max_nerr),
              100 * r.fast_sil.rate_raw(), 100 * r.fast_sil.rate(), 100 * r.fast_rand.rate_raw());
}

void expect_robust(const Tally& t, const char* what) {
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

void check_kind(Kind kind) {
  Rng rng(0x5eed0000u + unsigned(kind));
  print_header();
  Result total, hard, easy;
  std::vector<std::pair<ld, Result>> by_dist;
  for (const Config& cf : configs(kind)) {
    Result r;
    for (int prim = 0; prim < 4; ++prim) r.add(run_prim(make_round(cf, rng), cf.dist_r, 500, 200, rng));
    print_row(kind_name(kind), cf.translate, cf.len_r, cf.dist_r, r);
    total.add(r);
    auto it = std::find_if(by_dist.begin(), by_dist.end(), [&](const auto& e) { return e.first == cf.dist_r; });
    (it == by_dist.end() ? by_dist.emplace_back(cf.dist_r, Result{}).second : it->second).add(r);
    // The range the architecture notes measured Quilez's capsule on: 1e2..1e5 radii.
    if (cf.dist_r >= 1e2L && cf.dist_r <= 1e5L) hard.add(r);
    if (cf.dist_r <= 1e1L && cf.len_r <= 1) easy.add(r);
  }
  std::printf("%s silhouette rays by distance (all lengths, both translations): raw disagreement robust / fast\n",
              kind_name(kind));
  for (const auto& [dr, r] : by_dist)
    std::printf("  D/r %6.0Lg: robust %7.3f%% (outside band %.1e, band %5.1f%%)   fast %6.2f%%\n", dr,
                100 * r.robust_sil.rate_raw(), r.robust_sil.rate(), 100 * r.robust_sil.amb_rate(),
                100 * r.fast_sil.rate_raw());
  std::printf("%s silhouette rays from 1e2..1e5 radii: fast (as written) disagrees on %.1f%% (%.1f%% outside the "
              "band); robust on %.3f%% (%.1e outside the band)\n",
              kind_name(kind), 100 * hard.fast_sil.rate_raw(), 100 * hard.fast_sil.rate(),
              100 * hard.robust_sil.rate_raw(), hard.robust_sil.rate());
  Tally robust = total.robust_sil;
  robust.add(total.robust_rand);
  expect_robust(robust, kind_name(kind));
  // Where its digits suffice (close and short) the fast variant must be right too:
  // this checks its adaptation to non-unit directions, both roots and the contract.
  Tally fast_easy = easy.fast_sil;
  fast_easy.add(easy.fast_rand);
  EXPECT_EQ(fast_easy.flips, 0) << kind_name(kind) << ": fast variant, easy rays";
  EXPECT_EQ(fast_easy.t_bad + fast_easy.n_bad + fast_easy.u_bad, 0) << kind_name(kind) << ": fast variant, easy rays";
  // The hard range must really be hard: the test would prove nothing if its rays did
  // not trouble the textbook formula (for the sphere: b^2 - c).
  EXPECT_GT(hard.fast_sil.rate_raw(), 10 * hard.robust_sil.rate_raw() + 1e-2) << kind_name(kind);
}

TEST(Intersectors, CapsuleMatchesOracle) { check_kind(Kind::Capsule); }
TEST(Intersectors, RoundConeMatchesOracle) { check_kind(Kind::Cone); }
TEST(Intersectors, SphereMatchesOracle) { check_kind(Kind::Sphere); }

// ---------------------------------------------------------------- degenerate shapes

Round cone(glm::vec3 a, float ra, glm::vec3 b, float rb) { return {Kind::Cone, a, b, ra, rb}; }

TEST(Intersectors, DegenerateShapesMatchOracle) {
  Rng rng(0xde9e);
  glm::vec3 c(0.3f, -0.2f, 0.7f), w = glm::normalize(glm::vec3(1, 2, 3));
  float r = 1e-3f;
  struct Named {
    const char* name;
    Round p;
  };
  std::vector<Named> prims = {
      {"capsule, zero length", {Kind::Capsule, c, c, r, r}},
      {"cone, zero length", cone(c, r, c, 0.5f * r)},
      {"cone, b inside a", cone(c, r, c + 0.3f * r * w, 0.5f * r)},
      {"cone, a inside b", cone(c, 0.2f * r, c + 0.5f * r * w, r)},
      {"cone, nearly contained", cone(c, r, c + 0.5005f * r * w, 0.5f * r)},
      {"cone, equal radii", cone(c, r, c + 30.0f * r * w, r)},
      {"cone, point end", cone(c, r, c + 10.0f * r * w, 0.0f)},
      {"cone, negative end", cone(c, -r, c + 10.0f * r * w, r)},
      {"cone, long point end", cone(c, r, c + 1e4f * r * w, 0.0f)},
  };
  print_header();
  Tally robust;
  for (const Named& nm : prims)
    for (ld dr : {1e1L, 1e3L}) {
      Result res = run_prim(nm.p, dr, 1000, 500, rng);
      print_row(kind_name(nm.p.kind), 0, lenl(to_ld(nm.p.b) - to_ld(nm.p.a)) / r, dr, res);
      std::printf("    (%s)\n", nm.name);
      robust.add(res.robust_sil);
      robust.add(res.robust_rand);
    }
  expect_robust(robust, "degenerate shapes");
}

// The degenerate cases give exactly the simpler primitive's surface.
TEST(Intersectors, DegenerateShapesAgreeWithSimplerKernels) {
  Rng rng(0x51);
  glm::vec3 c(0.3f, -0.2f, 0.7f), w = glm::normalize(glm::vec3(-1, 2, 0.5f));
  float r = 0.01f;
  Round sphere{Kind::Sphere, c, c, r, r};
  Round zero_capsule{Kind::Capsule, c, c, r, r};
  Round contained = cone(c, r, c + 0.4f * r * w, 0.5f * r);
  Round zero_cone = cone(c + 0.f * w, 0.3f * r, c, r);
  Round capsule{Kind::Capsule, c, c + 20.0f * r * w, r, r};
  Round equal = cone(c, r, c + 20.0f * r * w, r);
  int bad = 0, hits = 0;
  for (int i = 0; i < 20000; ++i) {
    Vld o = to_ld(c) + (5 * ld(r)) * rand_unit(rng);
    Vld aim = to_ld(c) + (ld(r) * 1.2L * std::cbrt(uni(rng, 0, 1))) * rand_unit(rng) + uni(rng, 0, 20 * r) * to_ld(w);
    auto [of, df] = aimed_ray(o, aim, rng);
    auto same = [&](const Round& x, const Round& y, float rel) {
      for (int fast = 0; fast < 2; ++fast) {
        KV::PrimHit hx = run_kernel(x, fast, of, df), hy = run_kernel(y, fast, of, df);
        hits += hx.hit;
        if (hx.hit != hy.hit || (hx.hit && std::fabs(hx.t - hy.t) * glm::length(df) > rel * r)) ++bad;
      }
    };
    same(zero_capsule, sphere, 1e-5f);
    same(contained, sphere, 1e-5f);
    same(zero_cone, sphere, 1e-5f);
    same(equal, capsule, 1e-4f); // different formulas: agree up to rounding (and silhouettes)
  }
  std::printf("degenerate vs simpler kernels: %d hits, %d disagreements\n", hits, bad);
  EXPECT_GT(hits, 20000);
  EXPECT_LE(bad, 20); // equal-radii cone vs capsule may differ on a handful of silhouette rays
}

TEST(Intersectors, NoSurfaceOrInvalidRayMisses) {
  Rng rng(0x0);
  glm::vec3 c(0.1f, 0.2f, 0.3f), w(0, 0, 1);
  float nan = std::numeric_limits<float>::quiet_NaN();
  std::vector<Round> none = {
      {Kind::Capsule, c, c + w, 0.0f, 0.0f},  {Kind::Capsule, c, c + w, -1.0f, -1.0f},
      {Kind::Capsule, c, c + w, nan, nan},    {Kind::Sphere, c, c, 0.0f, 0.0f},
      {Kind::Sphere, c, c, nan, nan},         {Kind::Sphere, c, c, -1.0f, -1.0f},
      cone(c, 0.0f, c + w, 0.0f),             cone(c, nan, c + w, -1.0f),
      cone(c, -1.0f, c + w, 0.0f),            cone(c, nan, c, nan),
  };
  int hits = 0, rays = 0;
  for (const Round& p : none)
    for (int i = 0; i < 200; ++i) {
      Vld o = to_ld(c) + 3.0L * rand_unit(rng);
      auto [of, df] = aimed_ray(o, to_ld(c) + uni(rng, 0, 1) * to_ld(w), rng);
      for (int fast = 0; fast < 2; ++fast) {
        hits += run_kernel(p, fast, of, df).hit;
        ++rays;
      }
    }
  // Invalid rays against real primitives (robust variants; the oracle's contract).
  std::vector<Round> some = {{Kind::Capsule, c, c + w, 0.5f, 0.5f}, {Kind::Sphere, c, c, 0.5f, 0.5f},
                             cone(c, 0.5f, c + w, 0.2f)};
  float inf = kInfF;
  glm::vec3 o(0.1f, 0.2f, -5.0f), d(0, 0, 1);
  for (const Round& p : some) {
    EXPECT_TRUE(run_kernel(p, false, o, d).hit) << kind_name(p.kind);
    hits += run_kernel(p, false, glm::vec3(nan, 0, 0), d).hit;
    hits += run_kernel(p, false, glm::vec3(inf, 0, 0), d).hit;
    hits += run_kernel(p, false, o, glm::vec3(0)).hit;
    hits += run_kernel(p, false, o, glm::vec3(nan, 0, 1)).hit;
    hits += run_kernel(p, false, o, d, nan, inf).hit;
    hits += run_kernel(p, false, o, d, 0, nan).hit;
    hits += run_kernel(p, false, o, d, 10, 1).hit;
    hits += run_kernel(p, false, o, d, 0, 4).hit; // the surface is beyond tmax
    rays += 8;
  }
  EXPECT_EQ(hits, 0) << "of " << rays;
}

// ---------------------------------------------------------------- self window and inside rays

// A ray from a surface point rounded to fp32 starts on a crossing at tcross (signed
// distance of the rounded origin from the exact tangent plane over d.n), which the
// kernel places within about e_t. Held: well inside the self window, the kernel must
// ignore it. Off: well outside (the rounding moved the origin further than the window
// reaches; the window scales with r and |o - c|, not with |o|), the kernel must agree
// with the oracle, which sees the same rounded origin. Between: too close to call.
struct StartTally {
  long rays = 0, held = 0, held_hits = 0, off = 0, off_flips = 0;
  void add(ld tcross, ld tself, ld e_t, bool kernel_hit, bool oracle_hit) {
    ++rays;
    if (std::fabs(tcross) + e_t < 0.5L * tself) {
      ++held;
      held_hits += kernel_hit;
    } else if (std::fabs(tcross) > 2 * (tself + e_t)) {
      ++off;
      off_flips += kernel_hit != oracle_hit;
    }
  }
  void report(const char* what) const {
    std::printf("%s: %ld rays; %ld start well inside the window (robust hits on them: %ld); %ld start beyond it "
                "(robust disagrees with the oracle on %ld); %ld at its edge\n",
                what, rays, held, held_hits, off, off_flips, rays - held - off);
  }
  void check(const char* what) const {
    report(what);
    EXPECT_GT(held, rays / 2) << what << ": the test must mostly make rays that start on the surface";
    EXPECT_EQ(held_hits, 0) << what << ": self hits";
    EXPECT_EQ(off_flips, 0) << what;
  }
};

// Rays from a surface point: going out they must miss, going in they must report the
// far exit. Rays from inside report the exit.
TEST(Intersectors, SelfWindowAndInsideRays) {
  Rng rng(0x5e1f);
  long fast_self = 0, fast_rays = 0, in_rays = 0;
  StartTally outward;
  Tally inward, inside;
  for (Kind kind : {Kind::Capsule, Kind::Cone, Kind::Sphere})
    for (ld r : {1e-2L, 1e-4L})
      for (ld lr : {0.0L, 10.0L, 1e3L}) {
        if (kind == Kind::Sphere && lr > 0) continue;
        for (int prim = 0; prim < 8; ++prim) {
          Round p = make_round({kind, r, kind == Kind::Cone ? std::max<ld>(lr, 1) : lr, 0, 0}, rng);
          Geo g = geometry(p);
          Scale sc = round_scale(g);
          for (int i = 0; i < 300; ++i) {
            SurfPt s = sample_surface(g, rng);
            glm::vec3 of = to_f(s.p);
            Vld tang = rand_perp(rng, s.n);
            ld slope = uni(rng, 0, 3); // up to ~72 degrees from the normal
            ld scale = log_uni(rng, 1e-2, 1e2);
            glm::vec3 d_out = to_f(scale * unitl(s.n + slope * tang));
            glm::vec3 d_in = to_f(scale * unitl((-1.0L) * s.n + slope * tang));
            Vld dl = to_ld(d_out);
            ld dn = dotl(dl, s.n), dd = dotl(dl, dl);
            ld tcross = -dotl(to_ld(of) - s.p, s.n) / dn;
            ld tself = masq::oracle::self_window_t(rmax(g), to_ld(of) - g.c, dd, g.len);
            ld e_t = 4 * kU * (lenl(to_ld(of) - g.c) + g.len + rmax(g)) / std::fabs(dn);
            outward.add(tcross, tself, e_t, run_kernel(p, false, of, d_out).hit,
                        run_oracle(p, ld_ray(of, d_out)).hit);
            compare(run_kernel(p, false, of, d_in), run_oracle(p, ld_ray(of, d_in)), ld_ray(of, d_in), sc, inward);
            ++in_rays;
            // Fast variants: a self hit is a hit on the way out, or t ~ 0 on the way in.
            KV::PrimHit fo = run_kernel(p, true, of, d_out), fi = run_kernel(p, true, of, d_in);
            fast_rays += 2;
            fast_self += fo.hit + (fi.hit && fi.t * glm::length(d_in) < 0.01f * float(rmin(g)));
            // From inside: a point of the ball at axial fraction q, well within it.
            ld q = uni(rng, 0, 1);
            ld rq = g.ball ? rmax(g) : g.ra + q * (g.rb - g.ra);
            Vld centre = g.ball ? (g.ra >= g.rb ? g.a : g.b) : g.a + q * (g.b - g.a);
            Vld pin = centre + (0.8L * rq * std::cbrt(uni(rng, 0, 1))) * rand_unit(rng);
            auto [oi, di] = aimed_ray(pin, pin + rand_unit(rng), rng);
            PrimRay ray = ld_ray(oi, di);
            compare(run_kernel(p, false, oi, di), run_oracle(p, ray), ray, sc, inside);
          }
        }
      }
  outward.check("capsule/cone/sphere, outward from the surface");
  std::printf("fast variants (no window): self hits on %.1f%% of %ld surface rays\n",
              100.0 * double(fast_self) / double(fast_rays), fast_rays);
  expect_robust(inward, "inward from the surface");
  EXPECT_EQ(inward.flips_raw, 0);
  EXPECT_EQ(inward.n, in_rays);
  expect_robust(inside, "from inside");
  EXPECT_EQ(inside.flips_raw, 0);
  EXPECT_EQ(inside.amb, 0);
}

// ---------------------------------------------------------------- triangles

struct Tri {
  glm::vec3 v0, v1, v2;
};
K::Triangle ktri(const Tri& t) {
  return {{t.v0.x, t.v0.y, t.v0.z}, {t.v1.x, t.v1.y, t.v1.z}, {t.v2.x, t.v2.y, t.v2.z}, {0, 0, 0}};
}

TEST(Intersectors, TrianglesMatchOracle) {
  Rng rng(0x7a1);
  std::printf("triangles: size S, origin distance D, translation T\n");
  Tally robust_all, fast_all;
  StartTally surface_steep, surface_any;
  long fast_self = 0, fast_rays = 0;
  for (ld T : {0.0L, 1e5L})
    for (ld S : {1e-3L, 1.0L})
      for (ld dist_s : {1.0L, 1e2L, 1e4L}) {
        if (T > 0 && S < 1) continue; // the 1e5 grid (2^-7) would collapse the triangle
        Tally robust, fast;
        for (int k = 0; k < 20; ++k) {
          Vld base = Vld{uni(rng, -1, 1), uni(rng, -1, 1), uni(rng, -1, 1)} + Vld{T, T, T};
          Tri tr{to_f(base), to_f(base + S * rand_unit(rng)), to_f(base + S * rand_unit(rng))};
          Vld p0 = to_ld(tr.v0), p1 = to_ld(tr.v1), p2 = to_ld(tr.v2);
          Vld nrm = crossl(p1 - p0, p2 - p0);
          ld emax = std::max({lenl(p1 - p0), lenl(p2 - p1), lenl(p0 - p2)});
          ld hmin = lenl(nrm) / emax; // smallest height
          if (!(hmin > 1e-2L * S)) continue;
          Scale sc{p0, emax, hmin, kInfL, hmin};
          for (int i = 0; i < 150; ++i) {
            // Aim at barycentrics in [-0.2, 1.2], half of them within 1e-3..1e-1 of an edge.
            ld bu = uni(rng, -0.2, 1.2), bv = uni(rng, -0.2, 1.2);
            if (i % 2 == 0) {
              ld e = log_uni(rng, 1e-3, 1e-1) * (uni(rng, 0, 1) < 0.5 ? -1 : 1);
              bu = uni(rng, 0, 1);
              bv = i % 4 == 0 ? e : 1 - bu - e;
            }
            Vld aim = p0 + bu * (p1 - p0) + bv * (p2 - p0);
            Vld o = aim + (dist_s * S) * rand_unit(rng);
            auto [of, df] = aimed_ray(o, aim, rng);
            PrimRay ray = ld_ray(of, df);
            PrimResult ref = masq::oracle::oracle_triangle(tr.v0, tr.v1, tr.v2, ray);
            // A lateral error e moves the plane crossing by e / cos(i) in the plane:
            // the barycentric band is relative to hmin cos(i).
            Scale sci = sc;
            sci.r = hmin * std::max<ld>(std::fabs(dotl(unitl(nrm), ray.d)) / lenl(ray.d), 1e-6L);
            compare(KV::intersect_triangle(ktri(tr), of, df, 0, kInfF), ref, ray, sci, robust);
            compare(KV::intersect_triangle_fast(ktri(tr), of, df, 0, kInfF), ref, ray, sci, fast);
          }
          // Rays leaving a point of the triangle must not hit it again. Only where fp32
          // can place a point on the triangle within the window (8 u |o - v0|): near the
          // world origin and not much smaller than its distance from it.
          for (int i = 0; i < (T == 0 && S == 1 ? 50 : 0); ++i) {
            ld bu = uni(rng, 0.05, 0.9), bv = uni(rng, 0.05, 0.95 - bu);
            Vld pt = p0 + bu * (p1 - p0) + bv * (p2 - p0);
            glm::vec3 of = to_f(pt);
            Vld un = unitl(nrm);
            Vld dir = rand_unit(rng);
            bool steep = i % 2 == 0; // half of them at least 60 degrees from the plane
            if (steep) dir = unitl((dotl(dir, un) < 0 ? -1.0L : 1.0L) * un + uni(rng, 0, 0.55) * rand_perp(rng, un));
            glm::vec3 df = to_f(log_uni(rng, 1e-2, 1e2) * dir);
            Vld dl = to_ld(df);
            ld dn = dotl(dl, un);
            ld tcross = -dotl(to_ld(of) - pt, un) / dn;
            ld tself = masq::oracle::self_window_t(0, to_ld(of) - p0, dotl(dl, dl));
            PrimRay ray = ld_ray(of, df);
            (steep ? surface_steep : surface_any)
                .add(tcross, tself, 0, KV::intersect_triangle(ktri(tr), of, df, 0, kInfF).hit,
                     masq::oracle::oracle_triangle(tr.v0, tr.v1, tr.v2, ray).hit);
            ++fast_rays;
            fast_self += KV::intersect_triangle_fast(ktri(tr), of, df, 0, kInfF).hit;
          }
        }
        std::printf("  T %6.0Lg S %5.0Lg D/S %5.0Lg | %5ld rays, band %5.1f%% | robust %.1e (raw %.1e) | fast raw %.2f%% "
                    "(outside band %.2f%%)\n",
                    T, S, dist_s, robust.n, 100 * robust.amb_rate(), robust.rate(), robust.rate_raw(),
                    100 * fast.rate_raw(), 100 * fast.rate());
        robust_all.add(robust);
        fast_all.add(fast);
      }
  expect_robust(robust_all, "triangles");
  std::printf("Moller-Trumbore: %.3f%% raw, %.2e outside the band\n", 100 * fast_all.rate_raw(), fast_all.rate());
  // The triangle window (8 u |o - v0| / |d|) has no size term, while t from any fp32
  // formula errs by ~ u max|o - v_i| / cos(incidence): rays leaving at a grazing angle
  // can still see their own triangle. Held to zero only for steep rays; printed for all.
  surface_steep.check("triangles, rays from the surface, >= 60 deg from the plane");
  surface_any.report("triangles, rays from the surface, any direction");
  EXPECT_LT(double(surface_any.held_hits), 0.01 * double(surface_any.held));
  std::printf("Moller-Trumbore (no window): self hits on %.1f%% of %ld surface rays\n",
              100.0 * double(fast_self) / double(fast_rays), fast_rays);
}

} // namespace
