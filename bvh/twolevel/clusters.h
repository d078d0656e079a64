// Oriented clusters of thin primitives (method cluster, docs/methods.md): primitives of
// one geometry grouped by axis direction (antipodal directions are the same class) and
// then by position, so that one instance per cluster, rotating the cluster's dominant
// axis onto x, turns its members' local AABBs into tight world OBBs. Woop et al. 2014
// group by orientation similarity the same way; the masquerade paper names it as
// future work.
#pragma once
#include "bvh/bounds/aabb.h"
#include "bvh/bounds/prim_bounds.h"
#include "scenes/scene.h"
#include <cstdint>
#include <span>
#include <vector>

namespace masq {

struct ClusterOptions {
  int max_size = 32;     // members per cluster (2..256); docs/methods.md shows the sweep
  int classes = 32;      // orientation classes over the hemisphere of axis directions (1..1024)
  // The cluster BLAS's SAH price of a node visit, in intersector calls (>= 1). Members
  // are parallel and side by side, so at price 1 the SAH splits down to one member per
  // leaf: the fewest intersector calls, at 2-2.5x the node bytes of ref's BLAS. 4 fills
  // the leaves (cluster bytes <= ref's) at ~2 more calls per ray. docs/methods.md.
  double leaf_price = 4.0;
};

struct Cluster {
  std::vector<std::int32_t> members; // primitive ids of the geometry
  glm::dmat3 axes{1.0};              // orthonormal columns; axes[0]: the dominant axis
  glm::dvec3 centre{0.0};            // object-space centre of the members' local box
  Aabb local_box;                    // members' hull box in the frame (axes, centre), exact in double
  // The members' own hull boxes in the frame, their areas summed in member order: the
  // cost model's price of the members inside the cluster (bvh/twolevel/method_plan.cpp),
  // found here beside local_box from the same supports.
  double member_area = 0;
};

// The class directions: `count` points spread evenly over the upper hemisphere (z >= 0).
std::vector<glm::dvec3> orientation_classes(int count);

// Each of `prims`' orientation class (of `classes`, orientation_classes) and its
// centroid in that class's frame, in the order of prims: the first pass of
// make_clusters, over every primitive's hull. It depends on the class count alone, so
// the cluster sizes auto tries share one (bvh/twolevel/build_accel.cpp).
struct ClassAssignment {
  int classes = 0;
  std::vector<std::uint32_t> class_of;
  std::vector<glm::dvec3> centroid;
};
ClassAssignment assign_classes(const Geometry& g, const std::vector<std::int32_t>& prims, int classes);

// Each cluster's members' hulls (ball_hull, in member order), per cluster in cluster order.
using ClusterHulls = std::vector<std::vector<BallHull>>;

// Whether hulls has one list per cluster of clusters, each as long as its members (what
// the cluster BLAS and the mix's plan check before they read a handed-out list).
bool hulls_match(const ClusterHulls& hulls, const std::vector<Cluster>& clusters);

// Clusters of the primitives `prims` of a capsule, round-cone or curve geometry: each
// orientation class split top-down (k-d, at multiples of max_size) until every part
// has at most opt.max_size members. Primitives without an axis join class 0.
// assigned: assign_classes(g, prims, opt.classes), when the caller has it; else made here.
// hulls: when given, set to the clusters' member hulls as make_clusters read them, for
// the cluster BLAS and auto's mix plan, which would read them again otherwise (a
// cluster's members lie anywhere in the geometry's arrays, and those reads missed the
// cache: perf, the hull reads were a tenth of auto's build of the bear).
std::vector<Cluster> make_clusters(const Geometry& g, const std::vector<std::int32_t>& prims,
                                   const ClusterOptions& opt, const ClassAssignment* assigned = nullptr,
                                   ClusterHulls* hulls = nullptr);

// Object space -> the cluster's local frame (rotation and translation).
Affine3 cluster_object_to_local(const Cluster& c);

// out (cleared first) := ball_hull of each of `members`, in order. One loop of
// independent reads: a cluster's members lie anywhere in the geometry's arrays, and read
// one at a time between the box arithmetic each read missed the cache on its own (perf:
// most of a cluster build's hull reads).
void member_hulls(const Geometry& g, std::span<const std::int32_t> members, std::vector<BallHull>& out);

} // namespace masq
