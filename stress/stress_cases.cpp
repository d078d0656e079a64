#include "stress/stress_cases.h"
#include "oracle/oracle.h"
#include "scenes/camera.h"
#include "scenes/curve_tools.h"
#include "masq/error.h"
#include <fmt/format.h>
#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

namespace masq::stress {

namespace {

constexpr int kPrims = 4;           // primitives per cell scene
constexpr double kU = 5.9604645e-8; // fp32 unit roundoff

std::string pow10_label(const char* what, double v) {
  return fmt::format("{}=1e{}", what, int(std::lround(std::log10(v))));
}


// Which primitive types a sweep point applies to (bit per PrimType).
constexpr unsigned kCapsuleBit = 1u << unsigned(PrimType::Capsule), kConeBit = 1u << unsigned(PrimType::RoundCone),
                   kCurveBit = 1u << unsigned(PrimType::Curve), kSphereBit = 1u << unsigned(PrimType::Sphere),
                   kTriangleBit = 1u << unsigned(PrimType::Triangle);
constexpr unsigned kTubes = kCapsuleBit | kConeBit | kCurveBit;
constexpr unsigned kAll = kTubes | kSphereBit | kTriangleBit;

// One sweep point: the parameters that differ from CellSpec's defaults (r = 1e-3,
// L/r = 100, D/r = 1e3, no offset). 0 keeps the default.
struct SweepPoint {
  const char* sweep;
  unsigned types;
  bool quick; // in the --quick subset (the ctest one): the hardest point of each sweep
  double radius, length_r, distance_r, offset;
};

// The sweep, in report order. Lengths are of the primitive (spheres have none); the
// camera cells look from D at a long primitive, so its far end is up to D + L/2 away
// (the band's D + L covers it). Spheres get the camera at their own size.
constexpr SweepPoint kSweep[] = {
    {"distance", kAll, true, 0, 0, 1e1, 0},
    {"distance", kAll, false, 0, 0, 1e2, 0},
    {"distance", kAll, false, 0, 0, 1e3, 0},
    {"distance", kAll, true, 0, 0, 1e4, 0},
    {"distance", kAll, false, 0, 0, 1e5, 0},
    {"distance", kAll, false, 0, 0, 1e6, 0},
    {"distance", kAll, true, 0, 0, 1e7, 0},
    {"length", kTubes | kTriangleBit, true, 0, 1, 0, 0},
    {"length", kTubes | kTriangleBit, false, 0, 1e1, 0, 0},
    {"length", kTubes | kTriangleBit, false, 0, 1e2, 0, 0},
    {"length", kTubes | kTriangleBit, false, 0, 1e3, 0, 0},
    {"length", kTubes | kTriangleBit, true, 0, 1e4, 0, 0},
    {"length", kTubes | kTriangleBit, false, 0, 1e5, 0, 0},
    {"length", kTubes | kTriangleBit, true, 0, 1e6, 0, 0},
    {"radius", kTubes | kSphereBit, false, 1e-1, 0, 0, 0},
    {"radius", kTubes | kSphereBit, false, 1e-3, 0, 0, 0},
    {"radius", kTubes | kSphereBit, true, 1e-5, 0, 0, 0},
    {"offset", kAll, false, 0, 0, 0, 1e1},
    {"offset", kAll, false, 0, 0, 0, 1e3},
    {"offset", kAll, false, 0, 0, 0, 1e5},
    {"offset", kAll, true, 0, 0, 0, 1e6},
    {"camera", kTubes | kTriangleBit, false, 0, 1e5, 1e4, 0},
    {"camera", kTubes | kTriangleBit, true, 0, 1e6, 1e4, 0},
    {"camera", kTubes | kTriangleBit, false, 0, 1e6, 1e5, 0},
    {"camera", kTubes | kTriangleBit, false, 0, 1e6, 1e6, 0},
    {"camera", kTubes | kTriangleBit, true, 0, 1e6, 1e7, 0},
    {"camera", kSphereBit, false, 0, 0, 1e4, 0},
    {"camera", kSphereBit, true, 0, 0, 1e7, 0},
};

CellSpec sweep_cell(PrimType t, const SweepPoint& p) {
  CellSpec c;
  c.type = t;
  c.sweep = p.sweep;
  if (p.radius > 0) c.radius = p.radius;
  if (p.length_r > 0) c.length_r = p.length_r;
  if (p.distance_r > 0) c.distance_r = p.distance_r;
  c.offset = p.offset;
  c.camera = c.sweep == "camera";
  if (c.camera)
    c.label = pow10_label("cam D/r", c.distance_r) + (p.length_r > 0 ? pow10_label(" L/r", c.length_r) : "");
  else if (p.distance_r > 0) c.label = pow10_label("D/r", c.distance_r);
  else if (p.length_r > 0) c.label = pow10_label("L/r", c.length_r);
  else if (p.radius > 0) c.label = pow10_label("r", c.radius);
  else c.label = pow10_label("offset", c.offset);
  return c;
}

} // namespace

std::vector<CellSpec> sweep_cells(const SweepOptions& opt) {
  std::vector<CellSpec> cells;
  for (PrimType t : opt.types) {
    CellSpec base;
    base.type = t;
    auto add = [&](CellSpec c) {
      if (opt.sweeps.empty() || std::find(opt.sweeps.begin(), opt.sweeps.end(), c.sweep) != opt.sweeps.end())
        cells.push_back(std::move(c));
    };
    for (const SweepPoint& p : kSweep)
      if ((p.types >> unsigned(t) & 1u) && (p.quick || !opt.quick)) add(sweep_cell(t, p));
    std::vector<std::string> degenerate;
    switch (t) {
      case PrimType::Capsule: degenerate = {"zero-length", "zero-radius"}; break;
      case PrimType::RoundCone: degenerate = {"contained", "zero-length", "zero-radius"}; break;
      case PrimType::Curve: degenerate = {"coincident", "flat-tangent", "zero-radius"}; break;
      case PrimType::Sphere: degenerate = {"zero-radius"}; break;
      case PrimType::Triangle: degenerate = {"collinear"}; break;
    }
    for (const std::string& d : degenerate) {
      CellSpec c = base;
      c.sweep = "degenerate";
      c.degenerate = d;
      c.label = d;
      add(c);
    }
    // Curves whose solid is not a tube about a smooth axis: a hairpin bent with a
    // radius of curvature near r (its legs' balls overlap), a cusp (zero speed, the
    // tangent turning by 180 degrees), and a control polygon folded back on itself.
    if (t == PrimType::Curve) {
      for (const char* d : {"bend", "cusp", "fold"}) {
        CellSpec c = base;
        c.sweep = "shape";
        c.degenerate = d;
        c.label = d;
        add(c);
      }
    }
  }
  if (opt.sweeps.empty() || std::find(opt.sweeps.begin(), opt.sweeps.end(), "invalid") != opt.sweeps.end()) {
    CellSpec inv;
    inv.type = PrimType::Capsule;
    inv.sweep = "invalid";
    inv.label = "nan/inf rays";
    cells.push_back(inv);
  }
  // Every cell's rays by its place in this list; then a curve cell per intersector,
  // each asked the same rays (labelled by the intersector past the first).
  std::vector<CellSpec> out;
  for (std::size_t i = 0; i < cells.size(); ++i) {
    cells[i].ray_seed = i;
    if (cells[i].type != PrimType::Curve) {
      out.push_back(cells[i]);
      continue;
    }
    for (CurveIsect ci : opt.curve_isects) {
      CellSpec c = cells[i];
      c.curve_isect = ci;
      if (ci != CurveIsect::Phantom) c.label += std::string(" ") + curve_isect_name(ci);
      out.push_back(std::move(c));
    }
  }
  return out;
}

namespace {

using Rng = std::mt19937_64;

glm::dvec3 random_unit(Rng& rng) {
  std::normal_distribution<double> g;
  for (;;) {
    glm::dvec3 v(g(rng), g(rng), g(rng));
    double l = glm::length(v);
    if (l > 1e-6) return v / l;
  }
}

glm::dvec3 perpendicular_to(const glm::dvec3& w, Rng& rng) {
  for (;;) {
    glm::dvec3 v = random_unit(rng);
    glm::dvec3 p = v - glm::dot(v, w) * w;
    double l = glm::length(p);
    if (l > 1e-3) return p / l;
  }
}

double uniform(Rng& rng, double a, double b) { return std::uniform_real_distribution<double>(a, b)(rng); }

// What the ray generators need of a primitive: a core point, the tangent and the
// radius at parameter s in [0,1] (sphere: its centre; triangle: a point inside).
struct Probe {
  PrimType type;
  std::array<glm::dvec3, 4> p{};
  double ra = 0, rb = 0;
  glm::dvec3 point(double s) const {
    switch (type) {
      case PrimType::Capsule:
      case PrimType::RoundCone: return p[0] + s * (p[1] - p[0]);
      case PrimType::Curve: {
        double t = 1 - s;
        return t * t * t * p[0] + 3 * t * t * s * p[1] + 3 * t * s * s * p[2] + s * s * s * p[3];
      }
      case PrimType::Sphere: return p[0];
      case PrimType::Triangle: return p[0] + s * (p[1] - p[0]);
    }
    return p[0];
  }
  glm::dvec3 tangent(double s) const {
    glm::dvec3 d;
    if (type == PrimType::Curve) {
      double t = 1 - s;
      d = 3 * t * t * (p[1] - p[0]) + 6 * t * s * (p[2] - p[1]) + 3 * s * s * (p[3] - p[2]);
      if (glm::length(d) == 0) d = p[3] - p[0];
    } else {
      d = p[1] - p[0];
    }
    double l = glm::length(d);
    return l > 0 ? d / l : glm::dvec3(0, 0, 1);
  }
  double radius(double s) const { return type == PrimType::RoundCone ? ra + s * (rb - ra) : ra; }
};

struct Built {
  Scene scene;
  std::vector<Probe> probes;
};

Built build_scene(const CellSpec& c, Rng& rng) {
  Built b;
  Geometry g;
  g.type = c.type;
  const double r = c.radius;
  const double L = c.length_r * r;
  const glm::dvec3 offset_dir = glm::normalize(glm::dvec3(1.0, 0.5, 0.25));
  const glm::dvec3 origin = c.offset * offset_dir;
  const double spacing = 3.0 * (L + 4.0 * r);
  const bool zero_r = c.degenerate == "zero-radius";
  for (int i = 0; i < kPrims; ++i) {
    glm::dvec3 centre = origin + glm::dvec3((i - 1.5) * spacing, uniform(rng, -1, 1) * r, uniform(rng, -1, 1) * r);
    glm::dvec3 w = random_unit(rng);
    glm::dvec3 m = perpendicular_to(w, rng);
    Probe pr;
    pr.type = c.type;
    double len = c.degenerate == "zero-length" ? 0.0 : L;
    glm::dvec3 a = centre - 0.5 * len * w, e = centre + 0.5 * len * w;
    float rf = zero_r ? 0.0f : float(r);
    switch (c.type) {
      case PrimType::Capsule:
        g.capsules.push_back({glm::vec3(a), glm::vec3(e), rf});
        pr.p = {glm::dvec3(glm::vec3(a)), glm::dvec3(glm::vec3(e))};
        pr.ra = pr.rb = rf;
        break;
      case PrimType::RoundCone: {
        float rb = 0.5f * rf;
        if (c.degenerate == "contained") e = a + 0.3 * r * w; // ball b inside ball a
        g.round_cones.push_back({glm::vec3(a), rf, glm::vec3(e), rb});
        pr.p = {glm::dvec3(glm::vec3(a)), glm::dvec3(glm::vec3(e))};
        pr.ra = rf;
        pr.rb = rb;
        break;
      }
      case PrimType::Curve: {
        CurvePrim cv{};
        std::array<glm::dvec3, 4> q = {a, a + (e - a) / 3.0 + 0.15 * L * m, a + 2.0 * (e - a) / 3.0 - 0.1 * L * m, e};
        if (c.degenerate == "coincident") q = {centre, centre, centre, centre};
        if (c.degenerate == "flat-tangent") q = {a, a, e, e};
        if (c.degenerate == "bend") q = {a, e, e + 2.5 * r * m, a + 2.5 * r * m};
        if (c.degenerate == "cusp") // (0,0) (1,1) (0,1) (1,0) in (w, m): C'(1/2) = 0
          q = {a, e + L * m, a + L * m, e};
        if (c.degenerate == "fold") q = {a, e, e, a};
        for (int k = 0; k < 4; ++k) {
          cv.p[std::size_t(k)] = glm::vec3(q[std::size_t(k)]);
          pr.p[std::size_t(k)] = glm::dvec3(cv.p[std::size_t(k)]);
        }
        cv.radius = rf;
        g.curves.push_back(cv);
        pr.ra = pr.rb = rf;
        break;
      }
      case PrimType::Sphere:
        g.spheres.push_back({glm::vec3(centre), rf});
        pr.p = {glm::dvec3(glm::vec3(centre))};
        pr.ra = pr.rb = rf;
        break;
      case PrimType::Triangle: {
        glm::dvec3 v0 = a, v1 = e, v2 = centre + 0.8 * L * m;
        if (c.degenerate == "collinear") v2 = v1; // two coincident vertices: no area
        unsigned base = unsigned(g.vertices.size());
        for (const glm::dvec3& v : {v0, v1, v2}) g.vertices.push_back(glm::vec3(v));
        g.triangles.push_back({base, base + 1, base + 2});
        pr.p = {glm::dvec3(glm::vec3(v0)), glm::dvec3(glm::vec3(v1)), glm::dvec3(glm::vec3(v2))};
        pr.ra = pr.rb = 0;
        break;
      }
    }
    b.probes.push_back(pr);
  }
  b.scene.name = fmt::format("stress {} {}", prim_type_key(c.type), c.label);
  b.scene.geometries.push_back(std::move(g));
  b.scene.instances.push_back({0, {}});
  return b;
}

// A point and direction for one ray of `kind` aimed at probe `pr` (world, double).
struct Aim {
  glm::dvec3 point, dir;
};

// With an eye (camera cells) the direction is eye -> point; the kinds that choose their
// own direction (grazing, axis-parallel) are replaced by silhouette and random rays by
// the caller.
Aim aim_triangle(const Probe& pr, RayKind kind, double L, const glm::dvec3* eye, Rng& rng) {
  glm::dvec3 e1 = pr.p[1] - pr.p[0], e2 = pr.p[2] - pr.p[0];
  glm::dvec3 n = glm::cross(e1, e2);
  double nl = glm::length(n);
  n = nl > 0 ? n / nl : glm::dvec3(0, 0, 1);
  double u = uniform(rng, 0, 1), v = uniform(rng, 0, 1);
  if (u + v > 1) {
    u = 1 - u;
    v = 1 - v;
  }
  glm::dvec3 inside = pr.p[0] + u * e1 + v * e2;
  switch (kind) {
    case RayKind::Silhouette: {
      // Just inside or outside an edge, relative offset 1e-6..1e-1 of the edge length.
      int k = int(uniform(rng, 0, 3));
      glm::dvec3 a = pr.p[std::size_t(k)], b = pr.p[std::size_t((k + 1) % 3)];
      glm::dvec3 mid = a + uniform(rng, 0, 1) * (b - a);
      glm::dvec3 towards = glm::normalize(inside - mid + 1e-30);
      double eps = std::pow(10.0, uniform(rng, -6, -1)) * L * (uniform(rng, 0, 1) < 0.5 ? -1 : 1);
      glm::dvec3 d = glm::normalize(n + 0.5 * random_unit(rng));
      glm::dvec3 at = mid + eps * towards;
      return {at, eye ? glm::normalize(at - *eye) : d};
    }
    case RayKind::Grazing: {
      glm::dvec3 t = perpendicular_to(n, rng);
      double ang = std::pow(10.0, uniform(rng, -4, -1));
      return {inside, glm::normalize(std::cos(ang) * t + std::sin(ang) * n)};
    }
    default: return {inside, eye ? glm::normalize(inside - *eye) : random_unit(rng)};
  }
}

// spread: how far from the core random and axis-parallel rays pass, in radii.
Aim aim_round(const Probe& pr, RayKind kind, const glm::dvec3* eye, double spread, Rng& rng) {
  // s slightly beyond [0,1] reaches the end caps.
  double s = pr.type == PrimType::Sphere ? 0.0 : uniform(rng, -0.05, 1.05);
  double sc = std::clamp(s, 0.0, 1.0);
  glm::dvec3 q = pr.point(sc);
  glm::dvec3 w = pr.tangent(sc);
  double r = pr.radius(sc);
  double eps = std::pow(10.0, uniform(rng, -6, -1)) * (uniform(rng, 0, 1) < 0.5 ? -1 : 1);
  switch (kind) {
    case RayKind::Silhouette: {
      glm::dvec3 d = eye ? glm::normalize(q - *eye) : random_unit(rng);
      // Offset perpendicular to the ray and (on the tube) to the axis: the ray then
      // passes the axis at distance r (1 + eps) (from an eye, to first order in r / D).
      glm::dvec3 n = glm::cross(d, w);
      if (s != sc || pr.type == PrimType::Sphere || glm::length(n) < 1e-3) n = perpendicular_to(d, rng);
      n = glm::normalize(n);
      glm::dvec3 at = q + r * (1 + eps) * n;
      return {at, eye ? glm::normalize(at - *eye) : d};
    }
    case RayKind::Grazing: {
      double ang = std::pow(10.0, uniform(rng, -4, -0.5));
      glm::dvec3 m = perpendicular_to(w, rng);
      glm::dvec3 d = glm::normalize(std::cos(ang) * w + std::sin(ang) * m);
      glm::dvec3 n = glm::normalize(glm::cross(d, m));
      return {q + r * (1 + eps) * n, d};
    }
    case RayKind::AxisParallel: {
      glm::dvec3 d(0.0);
      d[int(uniform(rng, 0, 3)) % 3] = uniform(rng, 0, 1) < 0.5 ? -1 : 1;
      return {q + 0.6 * spread * r * random_unit(rng) * uniform(rng, 0, 1), d};
    }
    default: {
      glm::dvec3 at = q + spread * r * random_unit(rng) * uniform(rng, 0, 1);
      return {at, eye ? glm::normalize(at - *eye) : random_unit(rng)};
    }
  }
}

// The camera's eye: distance_r radii from the first primitive's centre, off its axis
// (perpendicular to the chord, tilted up to 45 degrees towards it), so a long primitive
// is seen from head-on near the centre to grazing at its ends. Rounded to fp32 first:
// the rays start exactly there.
glm::dvec3 camera_eye(const Probe& pr, double D, Rng& rng) {
  glm::dvec3 c = pr.type == PrimType::Curve ? 0.5 * (pr.p[0] + pr.p[3]) : pr.point(0.5);
  if (pr.type == PrimType::Triangle) c = (pr.p[0] + pr.p[1] + pr.p[2]) / 3.0;
  glm::dvec3 w = pr.type == PrimType::Curve ? pr.p[3] - pr.p[0] : pr.p[1] - pr.p[0];
  glm::dvec3 dir = random_unit(rng);
  if (glm::length(w) > 0 && pr.type != PrimType::Sphere) {
    w = glm::normalize(w);
    dir = glm::normalize(perpendicular_to(w, rng) + uniform(rng, -1, 1) * w);
  }
  return glm::dvec3(glm::vec3(c + D * dir));
}

kernel::Ray invalid_ray(int i) {
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  kernel::Ray r = make_ray({0, 0, -1}, {0, 0, 1});
  switch (i % 6) {
    case 0: r.org[i % 3] = nan; break;
    case 1: r.dir[i % 3] = nan; break;
    case 2: r.org[i % 3] = (i & 8) ? inf : -inf; break;
    case 3: r.dir[0] = r.dir[1] = r.dir[2] = 0.0f; break;
    case 4: r.tmin = 2.0f; r.tmax = 1.0f; break;
    case 5: r.tmax = nan; break;
  }
  return r;
}

} // namespace

Cell make_cell(const CellSpec& spec, int nrays, std::uint64_t seed) {
  if (nrays <= 0) throw Error("stress: rays per cell must be positive");
  Rng rng(seed);
  Built b = build_scene(spec, rng);
  Cell cell;
  cell.spec = spec;
  cell.radius = spec.type == PrimType::Triangle ? spec.length_r * spec.radius : spec.radius;
  const double L = spec.length_r * spec.radius;
  const double D = spec.distance_r * spec.radius;
  cell.ambiguity = 4.0 * kU * (1.0 + (D + L) / cell.radius);
  cell.scene = std::move(b.scene);
  if (spec.sweep == "invalid") {
    for (int i = 0; i < nrays; ++i) {
      cell.rays.push_back(invalid_ray(i));
      cell.kinds.push_back(RayKind::Invalid);
    }
    return cell;
  }
  oracle::Oracle oracle(cell.scene);
  // Kind mix: silhouette-heavy, as the error concentrates there.
  const RayKind mix[] = {RayKind::Silhouette, RayKind::Silhouette, RayKind::Silhouette, RayKind::Grazing,
                         RayKind::AxisParallel, RayKind::Random, RayKind::SurfaceOut, RayKind::SurfaceIn};
  int misses = 0; // surface-start rays that found no surface in a row
  // Random rays pass within 2 radii of the core; where the band is wider (D/r 1e7:
  // 2.4 r) every such ray would be ambiguous, so they spread over 4 bands instead and
  // the cell still checks that clear misses stay misses.
  const double spread = std::max(2.0, 4.0 * cell.ambiguity);
  glm::dvec3 eye_point(0.0);
  const glm::dvec3* eye = nullptr;
  if (spec.camera) {
    eye_point = camera_eye(b.probes[0], D, rng);
    eye = &eye_point;
  }
  while (int(cell.rays.size()) < nrays) {
    RayKind kind = mix[cell.rays.size() % 8];
    // An eye fixes each ray's direction: no grazing or axis-parallel choice there.
    if (eye && kind == RayKind::Grazing) kind = RayKind::Silhouette;
    if (eye && kind == RayKind::AxisParallel) kind = RayKind::Random;
    // A primitive without surface (radius 0) has no surface to start on: such rays
    // become random rays (which must all miss).
    if (misses > 20 && (kind == RayKind::SurfaceOut || kind == RayKind::SurfaceIn)) kind = RayKind::Random;
    // The camera looks at the first primitive only (its distance is the cell's D).
    const Probe& pr = b.probes[eye ? 0 : std::size_t(uniform(rng, 0, kPrims)) % kPrims];
    RayKind aim_kind = kind == RayKind::SurfaceOut || kind == RayKind::SurfaceIn ? RayKind::Random : kind;
    Aim aim = spec.type == PrimType::Triangle ? aim_triangle(pr, aim_kind, L, eye, rng)
                                              : aim_round(pr, aim_kind, eye, spread, rng);
    // Half of the rays get a non-unit direction (scaled by 1e-3..1e3): t must follow.
    double scale = uniform(rng, 0, 1) < 0.5 ? std::pow(10.0, uniform(rng, -3, 3)) : 1.0;
    glm::dvec3 org = eye ? *eye : aim.point - D * aim.dir;
    kernel::Ray ray = make_ray(org, aim.dir * scale, 0.0f, std::numeric_limits<float>::infinity());
    if (kind == RayKind::SurfaceOut || kind == RayKind::SurfaceIn) {
      // Start on the surface where this ray first hits, leaving outward or inward.
      oracle::OracleHit h = oracle.trace(ray);
      if (h.prim < 0) {
        ++misses;
        continue;
      }
      misses = 0;
      glm::dvec3 o(ray.org[0], ray.org[1], ray.org[2]), d(ray.dir[0], ray.dir[1], ray.dir[2]);
      glm::dvec3 p = o + double(h.t) * d;
      glm::dvec3 n = h.normal;
      glm::dvec3 nd = random_unit(rng);
      if (glm::dot(nd, n) < 0) nd = -nd;
      nd = glm::normalize(nd + n); // away from grazing
      if (kind == RayKind::SurfaceIn) nd = -nd;
      ray = make_ray(p, nd * scale, 0.0f, std::numeric_limits<float>::infinity());
    }
    cell.rays.push_back(ray);
    cell.kinds.push_back(kind);
  }
  return cell;
}

} // namespace masq::stress
