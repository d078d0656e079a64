// Which structure each primitive of a geometry goes into, per method:
//   ref:     every primitive in the geometry's BLAS (over AABBs);
//   masq:    thin primitives as masquerade instances, triangles in the BLAS;
//   cluster: capsules, round cones and curves in oriented clusters (bvh/twolevel/clusters.h),
//            spheres and triangles in the BLAS;
//   auto:    per cluster of the cluster method, the cluster or each member on its own
//            as a BLAS leaf or a masquerade instance, whichever the surface-area cost
//            model below says is cheaper (docs/methods.md).
#pragma once
#include "bvh/twolevel/clusters.h"
#include "bvh/bounds/obb.h"
#include "bvh/packed_scene.h"
#include "scenes/scene.h"
#include <cstdint>
#include <vector>

namespace masq {

// Relative prices of the work a ray does, for method auto: one wide-node visit (box
// tests of up to 4 children), one instance transform (with the masquerade unit-box
// test), one capsule intersector call (other types: isect_type_factor in
// bvh/twolevel/structure_cost.h). Only their ratios matter. The defaults are the whole-structure
// model's, fitted on the cpu and opencl backends (docs/methods.md).
struct CostPrices {
  double node = 1.0;
  double transform = 1.5;
  double isect = 2.5;
};

// The per-cluster planner's prices (the "mix" candidate of auto). Its per-primitive
// model cannot see that each new TLAS entry deepens and widens the TLAS, so it charges
// a transform far above its measured price; the whole-structure comparison then judges
// the mix against ref, masq and cluster with the real prices.
inline constexpr CostPrices kMixPlannerPrices{1.0, 10.0, 2.0};

struct GeometryPlan {
  std::vector<std::int32_t> blas_prims; // in the geometry's ordinary BLAS
  std::vector<std::int32_t> masq_prims; // masquerade instances
  std::vector<Cluster> clusters;        // cluster instances
  // clusters' member hulls, where the plan read them (else empty: the BLAS build reads them)
  ClusterHulls cluster_hulls;
};

struct PlanOptions {
  ClusterOptions cluster;
  CurveObb curve_obb = CurveObb::Tight;
  CostPrices prices;
};

// 0 .. primitive_count - 1: the primitives a plan places (make_clusters' prims).
std::vector<std::int32_t> every_primitive(const Geometry& g);

// clusters: what make_clusters gives for this geometry and opt.cluster's size and
// classes, when the caller has it already (auto's candidates that cluster alike share
// one clustering, bvh/twolevel/build_accel.cpp); nullptr: made here. hulls: the given
// clusters' member hulls, when the caller has them too.
GeometryPlan plan_geometry(const Geometry& g, Method method, const PlanOptions& opt,
                           const std::vector<Cluster>* clusters = nullptr, const ClusterHulls* hulls = nullptr);

// The cost model's expected work per ray reaching the geometry, in units of area
// times price (exposed for tests and the docs' tables).
struct PlanCosts {
  double ref = 0, masq = 0, cluster = 0, chosen = 0;
};
PlanCosts plan_costs(const Geometry& g, const PlanOptions& opt);

} // namespace masq
