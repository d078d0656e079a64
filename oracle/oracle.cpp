#include "oracle/oracle.h"
#include "oracle/oracle_prims.h"
#include "oracle/prim_common.h"
#include <algorithm>
#include <cmath>
#include <limits>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace masq::oracle {

namespace {

using ld = long double;
using detail::kInf;
using detail::operator+;
using detail::operator-;
using detail::operator*;

// A ball in a primitive's object space that holds every point closer to it than
// `cutoff` relative clearances (PrimResult::clearance < cutoff): a ray segment that
// passes outside it neither hits the primitive nor counts as near it. Radius inf: never
// skipped (triangles, whose clearance is barycentric, not a distance).
struct Reach {
  Vld centre;
  ld radius = kInf;
};
// Segment a-b swept by balls of radius at most r: clearance = gap / r, and the gap exceeds
// cutoff * r wherever the segment stays farther than |b - a| / 2 + (1 + cutoff) r from
// the midpoint.
Reach segment_reach(const glm::vec3& a, const glm::vec3& b, ld r, ld cutoff) {
  Vld va = detail::from(a), vb = detail::from(b);
  return {ld(0.5) * (va + vb), ld(0.5) * detail::len(vb - va) + (1 + cutoff) * r};
}

// The oracle's table of primitive types: its intersector and reach for each, row i for PrimType(i).
struct OraclePrimRow {
  PrimType type;
  PrimResult (*intersect)(const Geometry& g, std::size_t p, const PrimRay& ray);
  Reach (*reach)(const Geometry& g, std::size_t p, ld cutoff);
};
constexpr OraclePrimRow prim_rows[] = {
    {PrimType::Triangle,
     [](const Geometry& g, std::size_t p, const PrimRay& ray) {
       const glm::uvec3& tri = g.triangles[p];
       return oracle_triangle(g.vertices[tri.x], g.vertices[tri.y], g.vertices[tri.z], ray);
     },
     [](const Geometry&, std::size_t, ld) { return Reach{}; }},
    {PrimType::Capsule, [](const Geometry& g, std::size_t p, const PrimRay& ray) { return oracle_capsule(g.capsules[p], ray); },
     [](const Geometry& g, std::size_t p, ld cutoff) {
       const CapsulePrim& c = g.capsules[p];
       return segment_reach(c.a, c.b, detail::nonneg(c.radius), cutoff);
     }},
    {PrimType::RoundCone,
     [](const Geometry& g, std::size_t p, const PrimRay& ray) { return oracle_round_cone(g.round_cones[p], ray); },
     [](const Geometry& g, std::size_t p, ld cutoff) { // clearance relative to max(ra, rb)
       const RoundConePrim& c = g.round_cones[p];
       return segment_reach(c.a, c.b, std::max(detail::nonneg(c.ra), detail::nonneg(c.rb)), cutoff);
     }},
    {PrimType::Sphere, [](const Geometry& g, std::size_t p, const PrimRay& ray) { return oracle_sphere(g.spheres[p], ray); },
     [](const Geometry& g, std::size_t p, ld cutoff) {
       const SpherePrim& s = g.spheres[p];
       return segment_reach(s.center, s.center, detail::nonneg(s.radius), cutoff);
     }},
    {PrimType::Curve, [](const Geometry& g, std::size_t p, const PrimRay& ray) { return oracle_curve(g.curves[p], ray); },
     [](const Geometry& g, std::size_t p, ld cutoff) {
       // The curve lies in its control points' hull, so within the ball about their mean
       // that holds them; its clearance is relative to its radius (oracle_curve).
       const CurvePrim& c = g.curves[p];
       Vld centre;
       for (const glm::vec3& q : c.p) centre = centre + ld(0.25) * detail::from(q);
       ld hull = 0;
       for (const glm::vec3& q : c.p) hull = std::max(hull, detail::len(detail::from(q) - centre));
       return Reach{centre, hull + (1 + cutoff) * detail::nonneg(c.radius)};
     }},
    {PrimType::Ribbon, [](const Geometry& g, std::size_t p, const PrimRay& ray) { return oracle_ribbon(g.ribbons[p], ray); },
     [](const Geometry&, std::size_t, ld) { return Reach{}; }}, // clearance from the strip's edges, as triangles'
};
static_assert(one_row_per_prim_type(prim_rows), "oracle prim rows: one row per PrimType, in enum order");

// Distance from the segment o + t d, t in [tmin, tmax], to the point c.
ld segment_distance(const PrimRay& ray, Vld c) {
  ld dd = detail::dot(ray.d, ray.d);
  ld t = std::clamp(detail::dot(c - ray.o, ray.d) / dd, ray.tmin, ray.tmax);
  return detail::len((ray.o + t * ray.d) - c);
}

PrimResult intersect(const Geometry& g, std::size_t p, const PrimRay& ray, ld cutoff) {
  const auto i = static_cast<std::size_t>(g.type);
  if (i >= prim_type_count) return PrimResult{};
  if (std::isfinite(cutoff)) {
    const Reach reach = prim_rows[i].reach(g, p, cutoff);
    // The margin keeps the skip on the safe side of this test's own rounding.
    if (segment_distance(ray, reach.centre) > reach.radius * (1 + 1e-9L)) return PrimResult{};
  }
  return prim_rows[i].intersect(g, p, ray);
}

} // namespace

Oracle::Oracle(const Scene& scene, OracleOptions options) : scene_(scene), options_(options) {
  for (const Instance& inst : scene.instances) {
    // Invert the 3x3 in long double by cofactors.
    ld m[3][3];
    for (int r = 0; r < 3; ++r)
      for (int col = 0; col < 3; ++col) m[r][col] = inst.object_to_world.linear[col][r];
    ld det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
             m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
    InstanceLd il{};
    il.geometry = int(inst.geometry);
    for (int r = 0; r < 3; ++r)
      for (int col = 0; col < 3; ++col) {
        int r1 = (col + 1) % 3, r2 = (col + 2) % 3, c1 = (r + 1) % 3, c2 = (r + 2) % 3;
        il.w2o[r][col] = (m[r1][c1] * m[r2][c2] - m[r1][c2] * m[r2][c1]) / det;
      }
    for (int r = 0; r < 3; ++r) {
      ld s = 0;
      for (int col = 0; col < 3; ++col) s += il.w2o[r][col] * inst.object_to_world.translation[col];
      il.w2o[r][3] = -s;
    }
    inst_.push_back(il);
  }
}

OracleHit Oracle::trace(const kernel::Ray& ray) const {
  OracleHit out;
  out.t = kInf;
  out.second_t = kInf;
  out.clearance = kInf;
  const ld wo[3] = {ray.org[0], ray.org[1], ray.org[2]}, wd[3] = {ray.dir[0], ray.dir[1], ray.dir[2]};
  for (ld x : {wo[0], wo[1], wo[2], wd[0], wd[1], wd[2]})
    if (!std::isfinite(x)) return out;
  if (wd[0] == 0 && wd[1] == 0 && wd[2] == 0) return out;
  if (!(ray.tmin <= ray.tmax)) return out;
  struct Near {
    ld clearance, t;
  };
  std::vector<Near> near;
  for (std::size_t i = 0; i < inst_.size(); ++i) {
    const InstanceLd& il = inst_[i];
    auto xf = [&](const ld* p, ld w) {
      return Vld{il.w2o[0][0] * p[0] + il.w2o[0][1] * p[1] + il.w2o[0][2] * p[2] + w * il.w2o[0][3],
                 il.w2o[1][0] * p[0] + il.w2o[1][1] * p[1] + il.w2o[1][2] * p[2] + w * il.w2o[1][3],
                 il.w2o[2][0] * p[0] + il.w2o[2][1] * p[1] + il.w2o[2][2] * p[2] + w * il.w2o[2][3]};
    };
    // Object space preserves t: the direction is mapped linearly, not renormalised.
    PrimRay pr{xf(wo, 1), xf(wd, 0), ray.tmin, ray.tmax};
    const Geometry& g = scene_.geometries[il.geometry];
    std::size_t n = g.primitive_count();
    for (std::size_t p = 0; p < n; ++p) {
      PrimResult c = intersect(g, p, pr, options_.exact_clearance_below);
      if (c.clearance < kInf) near.push_back({c.clearance, c.t_near});
      if (!c.hit) continue;
      if (c.t < out.t) {
        out.second_t = out.t;
        out.t = c.t;
        out.prim = int(p);
        out.geom = il.geometry;
        out.inst = int(i);
        // World normal: transpose of world->object applied to the object normal.
        const Vld& m = c.normal;
        ld n2[3];
        for (int k = 0; k < 3; ++k) n2[k] = il.w2o[0][k] * m.x + il.w2o[1][k] * m.y + il.w2o[2][k] * m.z;
        ld len = std::sqrt(n2[0] * n2[0] + n2[1] * n2[1] + n2[2] * n2[2]);
        out.normal = glm::dvec3(double(n2[0] / len), double(n2[1] / len), double(n2[2] / len));
      } else if (c.t < out.second_t) {
        out.second_t = c.t;
      }
    }
  }
  // Clearance only matters for primitives the ray passes before (or near) its hit.
  ld limit = out.prim >= 0 ? out.t * (1 + 1e-3L) + 1e-6L : kInf;
  for (const Near& nr : near)
    if (nr.t <= limit) out.clearance = std::min(out.clearance, nr.clearance);
  return out;
}

std::vector<OracleHit> Oracle::trace_all(const std::vector<kernel::Ray>& rays) const {
  std::vector<OracleHit> out(rays.size());
  // Each ray is traced alone into its own slot: the answer cannot depend on the split.
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, rays.size()), [&](const tbb::blocked_range<std::size_t>& r) {
    for (std::size_t i = r.begin(); i < r.end(); ++i) out[i] = trace(rays[i]);
  });
  return out;
}

} // namespace masq::oracle
