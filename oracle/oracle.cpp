#include "oracle/oracle.h"
#include <algorithm>
#include <cmath>
#include <limits>
#include <thread>

namespace masq::oracle {

namespace {

using ld = long double;
struct V {
  ld x, y, z;
};
V operator+(V a, V b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
V operator-(V a, V b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
V operator*(ld s, V a) { return {s * a.x, s * a.y, s * a.z}; }
ld dot(V a, V b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
V cross(V a, V b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
V from(const glm::vec3& v) { return {v.x, v.y, v.z}; }
const ld kInf = std::numeric_limits<ld>::infinity();

struct Candidate {
  bool hit = false;
  ld t = kInf;
  V normal{0, 0, 0};
  ld clearance = kInf;
  ld t_near = kInf; // where the ray passes the primitive (for clearance relevance)
};

// Roots of a t^2 + 2 b t + c = 0 (a > 0).
int roots(ld a, ld b, ld c, ld out[2]) {
  ld disc = b * b - a * c;
  if (disc < 0) return 0;
  ld s = std::sqrt(disc);
  out[0] = (-b - s) / a;
  out[1] = (-b + s) / a;
  return 2;
}

Candidate capsule(const CapsulePrim& cp, V o, V d, ld tmin, ld tmax) {
  Candidate c;
  ld r = cp.radius;
  if (!(r > 0)) return c;
  V a = from(cp.a), b = from(cp.b);
  V ba = b - a, oa = o - a;
  ld baba = dot(ba, ba), bard = dot(ba, d), baoa = dot(ba, oa), dd = dot(d, d);
  auto take = [&](ld t, V n) {
    if (t >= tmin && t <= tmax && t < c.t) {
      c.hit = true;
      c.t = t;
      c.normal = n;
    }
  };
  ld rt[2];
  if (baba > 0) {
    // Cylinder: |(oa + t d) x ba|^2 = r^2 |ba|^2, as a quadratic in t.
    ld qa = baba * dd - bard * bard;
    ld qb = baba * dot(oa, d) - baoa * bard;
    ld qc = baba * dot(oa, oa) - baoa * baoa - r * r * baba;
    if (qa > 0 && roots(qa, qb, qc, rt) == 2)
      for (ld t : rt) {
        ld y = baoa + t * bard;
        if (y >= 0 && y <= baba) {
          V p = oa + t * d;
          take(t, p - (y / baba) * ba);
        }
      }
  }
  for (int e = 0; e < 2; ++e) {
    V oc = e == 0 ? oa : o - b;
    if (roots(dd, dot(oc, d), dot(oc, oc) - r * r, rt) == 2)
      for (ld t : rt) {
        ld y = baoa + t * bard;
        if (baba == 0 || (e == 0 ? y <= 0 : y >= baba)) take(t, oc + t * d);
      }
  }
  // Clearance: distance from the ray's line to the segment (closest points of a line
  // and a clamped segment), compared with r.
  ld best = kInf, best_t = kInf;
  auto consider = [&](ld s) { // s: segment parameter in [0,1]
    s = std::clamp<ld>(s, 0, 1);
    V q = a + s * ba;
    ld t = dot(q - o, d) / dd;
    V diff = o + t * d - q;
    ld dist = std::sqrt(dot(diff, diff));
    if (dist < best) {
      best = dist;
      best_t = t;
    }
  };
  consider(0);
  consider(1);
  // Interior critical point of |oa + t d - s ba|^2 over (t, s).
  ld denom = baba * dd - bard * bard;
  if (baba > 0 && denom > 0) consider((dd * baoa - bard * dot(oa, d)) / denom);
  c.clearance = std::fabs(best - r) / r;
  c.t_near = best_t;
  return c;
}

Candidate triangle(const Geometry& g, const glm::uvec3& tri, V o, V d, ld tmin, ld tmax) {
  Candidate c;
  V p0 = from(g.vertices[tri.x]), p1 = from(g.vertices[tri.y]), p2 = from(g.vertices[tri.z]);
  V e1 = p1 - p0, e2 = p2 - p0;
  V pv = cross(d, e2);
  ld det = dot(e1, pv);
  if (det == 0) return c;
  V tv = o - p0;
  ld u = dot(tv, pv) / det;
  V qv = cross(tv, e1);
  ld v = dot(d, qv) / det;
  ld t = dot(e2, qv) / det;
  ld w = 1 - u - v;
  if (t >= tmin && t <= tmax) {
    c.clearance = std::min({std::fabs(u), std::fabs(v), std::fabs(w)});
    c.t_near = t;
    if (u >= 0 && v >= 0 && w >= 0) {
      c.hit = true;
      c.t = t;
      c.normal = cross(e1, e2);
    }
  }
  return c;
}

} // namespace

Oracle::Oracle(const Scene& scene) : scene_(scene) {
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
  V wo{ray.org[0], ray.org[1], ray.org[2]}, wd{ray.dir[0], ray.dir[1], ray.dir[2]};
  for (ld x : {wo.x, wo.y, wo.z, wd.x, wd.y, wd.z})
    if (!std::isfinite(x)) return out;
  if (dot(wd, wd) == 0 || !(ray.tmin <= ray.tmax)) return out;
  struct Near {
    ld clearance, t;
  };
  std::vector<Near> near;
  for (std::size_t i = 0; i < inst_.size(); ++i) {
    const InstanceLd& il = inst_[i];
    auto xf = [&](V p, ld w) {
      return V{il.w2o[0][0] * p.x + il.w2o[0][1] * p.y + il.w2o[0][2] * p.z + w * il.w2o[0][3],
               il.w2o[1][0] * p.x + il.w2o[1][1] * p.y + il.w2o[1][2] * p.z + w * il.w2o[1][3],
               il.w2o[2][0] * p.x + il.w2o[2][1] * p.y + il.w2o[2][2] * p.z + w * il.w2o[2][3]};
    };
    V o = xf(wo, 1), d = xf(wd, 0);
    const Geometry& g = scene_.geometries[il.geometry];
    std::size_t n = g.primitive_count();
    for (std::size_t p = 0; p < n; ++p) {
      Candidate c = g.type == PrimType::Capsule ? capsule(g.capsules[p], o, d, ray.tmin, ray.tmax)
                                                : triangle(g, g.triangles[p], o, d, ray.tmin, ray.tmax);
      if (c.clearance < kInf) near.push_back({c.clearance, c.t_near});
      if (!c.hit) continue;
      if (c.t < out.t) {
        out.second_t = out.t;
        out.t = c.t;
        out.prim = int(p);
        out.geom = il.geometry;
        out.inst = int(i);
        // World normal: transpose of world->object applied to the object normal.
        V n2{il.w2o[0][0] * c.normal.x + il.w2o[1][0] * c.normal.y + il.w2o[2][0] * c.normal.z,
             il.w2o[0][1] * c.normal.x + il.w2o[1][1] * c.normal.y + il.w2o[2][1] * c.normal.z,
             il.w2o[0][2] * c.normal.x + il.w2o[1][2] * c.normal.y + il.w2o[2][2] * c.normal.z};
        ld len = std::sqrt(dot(n2, n2));
        out.normal = glm::dvec3(double(n2.x / len), double(n2.y / len), double(n2.z / len));
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
  unsigned nt = std::max(1u, std::thread::hardware_concurrency());
  std::vector<std::thread> pool;
  for (unsigned t = 0; t < nt; ++t)
    pool.emplace_back([&, t] {
      for (std::size_t i = t; i < rays.size(); i += nt) out[i] = trace(rays[i]);
    });
  for (std::thread& th : pool) th.join();
  return out;
}

} // namespace masq::oracle
