#include "bvh/twolevel/method_plan.h"
#include "bvh/bounds/prim_bounds.h"
#include "masq/error.h"
#include "scenes/prim_table.h"
#include <algorithm>

namespace masq {

namespace {

bool has_surface(const Geometry& g, std::size_t p) { return hull_max_radius(ball_hull(g, p)) > 0.0; }

// Surface-area cost model (SAH-style: the chance that a ray reaching the geometry
// reaches a box is proportional to its area; all terms share that unknown factor).
//   BLAS leaf:   a node-share test of its AABB, then the intersector:  (node + isect) A_aabb
//   masquerade:  TLAS leaf test of its AABB, the transform and unit-box test, then the
//                intersector only inside the OBB:  (node + transform) A_aabb + isect A_obb
//   cluster:     TLAS leaf test and transform for the cluster's box, then per member a
//                node-share test and the intersector on its local (oriented) box:
//                (node + transform) A_cluster + sum (node + isect) A_local
struct Model {
  const Geometry& g;
  const PlanOptions& opt;
  double aabb(std::int32_t p) const { return hull_box(ball_hull(g, std::size_t(p))).area(); }
  double ref(std::int32_t p) const { return (opt.prices.node + opt.prices.isect) * aabb(p); }
  double masq(std::int32_t p) const {
    if (!has_surface(g, std::size_t(p))) return ref(p);
    double obb = primitive_obb(g, std::size_t(p), opt.curve_obb).area();
    return (opt.prices.node + opt.prices.transform) * aabb(p) + opt.prices.isect * obb;
  }
  double cluster(const Cluster& c) const {
    // What the TLAS sees: the members' AABBs together.
    Aabb world;
    double members = 0;
    for (std::int32_t p : c.members) {
      BallHull h = ball_hull(g, std::size_t(p));
      world.grow(hull_box(h));
      Aabb local;
      for (int k = 0; k < 3; ++k) {
        local.lo[k] = -h.support(-c.axes[k]);
        local.hi[k] = h.support(c.axes[k]);
      }
      members += local.area();
    }
    return (opt.prices.node + opt.prices.transform) * world.area() + (opt.prices.node + opt.prices.isect) * members;
  }
};

std::vector<std::int32_t> all_prims(const Geometry& g) {
  std::vector<std::int32_t> ids(g.primitive_count());
  for (std::size_t i = 0; i < ids.size(); ++i) ids[i] = std::int32_t(i);
  return ids;
}

bool clusterable(PrimType t) { return scene_prim_row(t).oriented; }

} // namespace

GeometryPlan plan_geometry(const Geometry& g, Method method, const PlanOptions& opt, const std::vector<Cluster>* given) {
  GeometryPlan plan;
  if (scene_prim_row(g.type).mesh || method == Method::Ref) {
    plan.blas_prims = all_prims(g);
    return plan;
  }
  if (method == Method::Masq) {
    for (std::int32_t p : all_prims(g))
      if (has_surface(g, std::size_t(p))) plan.masq_prims.push_back(p); // no surface: nothing to box
    return plan;
  }
  Model model{g, opt};
  if (!clusterable(g.type)) { // spheres: no orientation
    for (std::int32_t p : all_prims(g)) {
      if (method == Method::Auto && model.masq(p) < model.ref(p))
        plan.masq_prims.push_back(p);
      else
        plan.blas_prims.push_back(p);
    }
    return plan;
  }
  std::vector<Cluster> clusters = given ? *given : make_clusters(g, all_prims(g), opt.cluster);
  if (method == Method::Cluster) {
    plan.clusters = std::move(clusters);
    return plan;
  }
  for (Cluster& c : clusters) {
    double alone = 0;
    for (std::int32_t p : c.members) alone += std::min(model.ref(p), model.masq(p));
    if (c.members.size() > 1 && model.cluster(c) < alone) {
      plan.clusters.push_back(std::move(c));
      continue;
    }
    for (std::int32_t p : c.members) {
      if (model.masq(p) < model.ref(p) && has_surface(g, std::size_t(p)))
        plan.masq_prims.push_back(p);
      else
        plan.blas_prims.push_back(p);
    }
  }
  std::sort(plan.blas_prims.begin(), plan.blas_prims.end());
  return plan;
}

PlanCosts plan_costs(const Geometry& g, const PlanOptions& opt) {
  PlanCosts pc;
  if (!clusterable(g.type)) return pc;
  Model model{g, opt};
  for (const Cluster& c : make_clusters(g, all_prims(g), opt.cluster)) {
    double alone = 0;
    for (std::int32_t p : c.members) {
      pc.ref += model.ref(p);
      pc.masq += model.masq(p);
      alone += std::min(model.ref(p), model.masq(p));
    }
    double cl = model.cluster(c);
    pc.cluster += cl;
    pc.chosen += c.members.size() > 1 ? std::min(cl, alone) : alone;
  }
  return pc;
}

} // namespace masq
