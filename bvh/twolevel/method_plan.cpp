#include "bvh/twolevel/method_plan.h"
#include "bvh/binary/parallel.h"
#include "bvh/bounds/prim_bounds.h"
#include "masq/error.h"
#include "scenes/prim_table.h"
#include <algorithm>
#include <span>

namespace masq {

namespace {

// Whether a primitive has a surface to box: a ball of positive radius. Its balls are read
// directly: the whole BallHull that ball_hull makes and zeroes was half of a masquerade
// plan's instructions.
bool has_surface(const Geometry& g, std::size_t p) { return prim_max_radius(g, p) > 0.0f; }

// Surface-area cost model (SAH-style: the chance that a ray reaching the geometry
// reaches a box is proportional to its area; all terms share that unknown factor).
//   BLAS leaf:   a node-share test of its AABB, then the intersector:  (node + isect) A_aabb
//   masquerade:  TLAS leaf test of its AABB, the transform and unit-box test, then the
//                intersector only inside the OBB:  (node + transform) A_aabb + isect A_obb
//   cluster:     TLAS leaf test and transform for the cluster's box, then per member a
//                node-share test and the intersector on its local (oriented) box:
//                (node + transform) A_cluster + sum (node + isect) A_local
// One primitive's two prices, from one look at its hull.
struct PrimPrices {
  double ref = 0, masq = 0;
  bool surface = false; // a masquerade has something to box (else masq = ref)
};

struct Model {
  const Geometry& g;
  const PlanOptions& opt;
  PrimPrices prices(std::int32_t p) const { return prices(ball_hull(g, std::size_t(p))); }
  PrimPrices prices(const BallHull& h) const {
    const double aabb = hull_box(h).area();
    PrimPrices out;
    out.ref = (opt.prices.node + opt.prices.isect) * aabb;
    out.surface = hull_max_radius(h) > 0.0;
    out.masq = out.ref;
    if (out.surface) {
      double obb = primitive_obb(g, h, opt.curve_obb).area();
      out.masq = (opt.prices.node + opt.prices.transform) * aabb + opt.prices.isect * obb;
    }
    return out;
  }
  // hulls: the cluster's members' (ball_hull), in member order. The members' local
  // boxes are make_clusters' (Cluster::member_area).
  double cluster(const Cluster& c, std::span<const BallHull> hulls) const {
    // What the TLAS sees: the members' AABBs together.
    Aabb world;
    for (const BallHull& h : hulls) world.grow(hull_box(h));
    return (opt.prices.node + opt.prices.transform) * world.area() + (opt.prices.node + opt.prices.isect) * c.member_area;
  }
};

bool clusterable(PrimType t) { return scene_prim_row(t).oriented; }

} // namespace

std::vector<std::int32_t> every_primitive(const Geometry& g) {
  std::vector<std::int32_t> ids(g.primitive_count());
  for (std::size_t i = 0; i < ids.size(); ++i) ids[i] = std::int32_t(i);
  return ids;
}

GeometryPlan plan_geometry(const Geometry& g, Method method, const PlanOptions& opt, const std::vector<Cluster>* given,
                           const ClusterHulls* given_hulls) {
  GeometryPlan plan;
  if (scene_prim_row(g.type).mesh || method == Method::Ref) {
    plan.blas_prims = every_primitive(g);
    return plan;
  }
  if (method == Method::Masq) {
    for (std::int32_t p : every_primitive(g))
      if (has_surface(g, std::size_t(p))) plan.masq_prims.push_back(p); // no surface: nothing to box
    return plan;
  }
  Model model{g, opt};
  if (!clusterable(g.type)) { // spheres: no orientation
    for (std::int32_t p : every_primitive(g)) {
      const PrimPrices pp = model.prices(p);
      if (method == Method::Auto && pp.masq < pp.ref)
        plan.masq_prims.push_back(p);
      else
        plan.blas_prims.push_back(p);
    }
    return plan;
  }
  std::vector<Cluster> made;
  ClusterHulls made_hulls;
  if (!given) made = make_clusters(g, every_primitive(g), opt.cluster, nullptr, &made_hulls);
  const std::vector<Cluster>& clusters = given ? *given : made;
  const ClusterHulls* known_hulls = given ? given_hulls : &made_hulls;
  if (known_hulls && !hulls_match(*known_hulls, clusters))
    throw Error("plan: member hulls that are not the clusters'");
  if (method == Method::Cluster) {
    if (given) {
      plan.clusters = *given; // (the caller has their hulls)
      return plan;
    }
    plan.clusters = std::move(made);
    plan.cluster_hulls = std::move(made_hulls);
    return plan;
  }
  // Each cluster's verdict on all threads (each member's two prices found once), then
  // the plan assembled in cluster order.
  enum Verdict : char { kBlas, kMasq };
  std::vector<char> whole(clusters.size(), 0);       // the cluster kept as one instance
  std::vector<std::vector<char>> member(clusters.size()); // else per member: kBlas or kMasq
  parallel_chunks(clusters.size(), 16, [&](std::size_t c0, std::size_t c1) {
    std::vector<PrimPrices> pp;
    std::vector<BallHull> read; // read first, in one loop (member_hulls), where not known
    for (std::size_t ci = c0; ci < c1; ++ci) {
      const Cluster& c = clusters[ci];
      if (!known_hulls) member_hulls(g, c.members, read);
      const std::vector<BallHull>& hulls = known_hulls ? (*known_hulls)[ci] : read;
      pp.resize(c.members.size());
      double alone = 0;
      for (std::size_t j = 0; j < c.members.size(); ++j) {
        pp[j] = model.prices(hulls[j]);
        alone += std::min(pp[j].ref, pp[j].masq);
      }
      if (c.members.size() > 1 && model.cluster(c, hulls) < alone) {
        whole[ci] = 1;
        continue;
      }
      member[ci].resize(c.members.size());
      for (std::size_t j = 0; j < c.members.size(); ++j)
        member[ci][j] = pp[j].masq < pp[j].ref && pp[j].surface ? kMasq : kBlas;
    }
  });
  // The BLAS's primitives go in increasing id order: marked, then read in order (a sort
  // of all of them was a fifth of the plan, where the plan is ref's).
  std::vector<char> in_blas(g.primitive_count(), 0);
  for (std::size_t ci = 0; ci < clusters.size(); ++ci) {
    if (whole[ci]) {
      plan.clusters.push_back(given ? clusters[ci] : std::move(made[ci])); // a given clustering is shared
      if (known_hulls) plan.cluster_hulls.push_back(given ? (*known_hulls)[ci] : std::move(made_hulls[ci]));
      continue;
    }
    for (std::size_t j = 0; j < clusters[ci].members.size(); ++j) {
      const std::int32_t p = clusters[ci].members[j];
      if (member[ci][j] == kMasq) plan.masq_prims.push_back(p);
      else in_blas[std::size_t(p)] = 1;
    }
  }
  for (std::size_t p = 0; p < in_blas.size(); ++p)
    if (in_blas[p]) plan.blas_prims.push_back(std::int32_t(p));
  return plan;
}

PlanCosts plan_costs(const Geometry& g, const PlanOptions& opt) {
  PlanCosts pc;
  if (!clusterable(g.type)) return pc;
  Model model{g, opt};
  ClusterHulls hulls_of;
  const std::vector<Cluster> clusters = make_clusters(g, every_primitive(g), opt.cluster, nullptr, &hulls_of);
  for (std::size_t ci = 0; ci < clusters.size(); ++ci) {
    const Cluster& c = clusters[ci];
    const std::vector<BallHull>& hulls = hulls_of[ci];
    double alone = 0;
    for (const BallHull& h : hulls) {
      const PrimPrices pp = model.prices(h);
      pc.ref += pp.ref;
      pc.masq += pp.masq;
      alone += std::min(pp.ref, pp.masq);
    }
    double cl = model.cluster(c, hulls);
    pc.cluster += cl;
    pc.chosen += c.members.size() > 1 ? std::min(cl, alone) : alone;
  }
  return pc;
}

} // namespace masq
