#include "stress/stress_cases.h"
#include "stress/stress_prim_rows.h"
#include "stress/stress_random.h"
#include "oracle/oracle.h"
#include "scenes/camera.h"
#include "scenes/curve_tools.h"
#include "masq/error.h"
#include <fmt/format.h>
#include <algorithm>
#include <cmath>
#include <limits>

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
                   kTriangleBit = 1u << unsigned(PrimType::Triangle), kRibbonBit = 1u << unsigned(PrimType::Ribbon);
constexpr unsigned kTubes = kCapsuleBit | kConeBit | kCurveBit;
constexpr unsigned kAll = kTubes | kSphereBit | kTriangleBit | kRibbonBit;

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
    const StressPrimRow& row = stress_prim_row(t);
    for (const char* d : row.degenerates) {
      CellSpec c = base;
      c.sweep = "degenerate";
      c.degenerate = d;
      c.label = d;
      add(c);
    }
    for (const char* d : row.shapes) {
      CellSpec c = base;
      c.sweep = "shape";
      c.degenerate = d;
      c.label = d;
      add(c);
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
    if (!stress_prim_row(cells[i].type).per_curve_isect) {
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
  if (opt.shard_count < 1 || opt.shard_index < 0 || opt.shard_index >= opt.shard_count)
    throw Error("stress: shard " + std::to_string(opt.shard_index) + " of " + std::to_string(opt.shard_count) +
                " does not exist");
  std::erase_if(out, [&](const CellSpec& c) {
    const bool type_kept =
        opt.only_types.empty() || std::find(opt.only_types.begin(), opt.only_types.end(), c.type) != opt.only_types.end();
    return !type_kept || int(c.ray_seed % std::uint64_t(opt.shard_count)) != opt.shard_index;
  });
  return out;
}

namespace {

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
  const StressPrimRow& row = stress_prim_row(c.type);
  for (int i = 0; i < kPrims; ++i) {
    glm::dvec3 centre = origin + glm::dvec3((i - 1.5) * spacing, uniform(rng, -1, 1) * r, uniform(rng, -1, 1) * r);
    glm::dvec3 w = random_unit(rng);
    glm::dvec3 m = perpendicular_to(w, rng);
    Probe pr;
    pr.type = c.type;
    double len = c.degenerate == "zero-length" ? 0.0 : L;
    glm::dvec3 a = centre - 0.5 * len * w, e = centre + 0.5 * len * w;
    float rf = zero_r ? 0.0f : float(r);
    row.add(c, PrimPlace{centre, w, m, a, e, r, L, rf}, g, pr);
    b.probes.push_back(pr);
  }
  b.scene.name = fmt::format("stress {} {}", prim_type_key(c.type), c.label);
  b.scene.geometries.push_back(std::move(g));
  b.scene.instances.push_back({0, {}});
  return b;
}

// The camera's eye: distance_r radii from the first primitive's centre, off its axis
// (perpendicular to the chord, tilted up to 45 degrees towards it), so a long primitive
// is seen from head-on near the centre to grazing at its ends. Rounded to fp32 first:
// the rays start exactly there.
glm::dvec3 camera_eye(const Probe& pr, double D, Rng& rng) {
  const StressPrimRow& row = stress_prim_row(pr.type);
  glm::dvec3 c = row.centre(pr);
  glm::dvec3 w = row.chord(pr);
  glm::dvec3 dir = random_unit(rng);
  if (glm::length(w) > 0) {
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
  const StressPrimRow& row = stress_prim_row(spec.type);
  cell.radius = row.sized_by_length ? spec.length_r * spec.radius : spec.radius;
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
    Aim aim = row.aim(pr, aim_kind, AimFrom{L, eye, spread}, rng);
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
