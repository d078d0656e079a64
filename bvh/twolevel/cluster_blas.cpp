#include "bvh/twolevel/cluster_blas.h"
#include "bvh/bounds/obb.h"
#include "bvh/bounds/prim_bounds.h"
#include "bvh/nodes/wide_bvh.h"
#include "bvh/binary/parallel.h"
#include "masq/error.h"
#include <cmath>
#include <algorithm>
#include <cstring>
#include <string>

namespace masq {

namespace {

Affine3 compose(const Affine3& outer, const Affine3& inner) {
  Affine3 r;
  r.linear = outer.linear * inner.linear;
  r.translation = outer.linear * inner.translation + outer.translation;
  return r;
}

Mat3x4f frame_matrix(const PackedScene& ps, int si) {
  Mat3x4f m;
  std::memcpy(m.data(), ps.frames.at(std::size_t(si)).world_to_object, sizeof(float) * 12);
  return m;
}

// Surface area of the world parallelepiped that a local box becomes.
double parallelepiped_area(const Aabb& local, const Affine3& local_to_world) {
  glm::dvec3 e[3];
  for (int k = 0; k < 3; ++k) e[k] = local_to_world.linear[k] * (local.hi[k] - local.lo[k]);
  return 2.0 * (glm::length(glm::cross(e[0], e[1])) + glm::length(glm::cross(e[1], e[2])) +
                glm::length(glm::cross(e[2], e[0])));
}

// given: the members' hulls, when the caller has them (else read into `read`).
ClusterBlas build_cluster(const Scene& scene, const Geometry& g, const Cluster& c, const std::vector<int>& scene_insts,
                          const SahOptions& sah, std::span<const double> leaf_prices, const BuilderOptions& builder,
                          const PackedScene& ps, const std::vector<BallHull>* given, std::vector<BallHull>& read) {
  ClusterBlas out;
  Affine3 object_to_local = cluster_object_to_local(c);
  if (!given) member_hulls(g, c.members, read);
  const std::vector<BallHull>& hulls = given ? *given : read;
  // The stored world-to-local matrix of every scene instance, then each member's
  // local box as the union of its hull's exact boxes under the realised maps.
  std::vector<Aabb> local(c.members.size());
  for (int si : scene_insts) {
    Mat3x4f frame = frame_matrix(ps, si);
    Mat3x4f w2l = to_mat3x4f(compose(object_to_local, from_mat3x4f(frame)));
    Affine3 realised = realised_object_to_local(w2l, frame);
    const glm::dvec3 row_len = row_lengths(realised);
    for (std::size_t m = 0; m < hulls.size(); ++m) local[m].grow(hull_world_box(hulls[m], realised, row_len));
    out.stored.push_back(w2l);
  }
  for (const Aabb& b : local)
    for (int k = 0; k < 3; ++k)
      if (!std::isfinite(b.lo[k]) || !std::isfinite(b.hi[k])) {
        // Thrown by the caller, in cluster order, so the first bad cluster is named
        // whatever the thread count.
        out.error = "cluster: a member's local box in geometry ";
        return out;
      }
  // What every leaf price's instances share, found here once (on all threads) rather
  // than per price at the append: per scene instance the local-to-world map and the
  // members' exact world boxes together, and each member's world AABB and OBB areas
  // (the stats' sums, added there in this order).
  const std::size_t members = c.members.size();
  out.member_areas.resize(scene_insts.size() * members);
  for (std::size_t k = 0; k < scene_insts.size(); ++k) {
    const Affine3& o2w = scene.instances[std::size_t(scene_insts[k])].object_to_world;
    const Affine3 l2w = inverse(from_mat3x4f(out.stored[k]));
    out.local_to_world.push_back(l2w);
    const glm::dvec3 row_len = row_lengths(o2w);
    Aabb exact;
    for (std::size_t m = 0; m < members; ++m) {
      Aabb wb = hull_world_box(hulls[m], o2w, row_len);
      exact.grow(wb);
      out.member_areas[k * members + m] = {wb.area(), parallelepiped_area(local[m], l2w)};
    }
    out.exact.push_back(exact);
  }
  // A cluster's members are parallel and side by side, so their local boxes barely
  // overlap and the plain SAH splits down to one primitive per leaf: four times the
  // nodes of ref's BLAS (61 vs 26 B per primitive on the default scene). A traversal
  // price of 4 (the default leaf_price) fills the leaves (27 B) at ~2 more intersector
  // calls per ray; auto also tries price 1 (docs/methods.md). The prices' trees share
  // their binning (build_binned_sah_costs), each then refined on its own where the
  // builder reinserts.
  std::vector<double> traversal(leaf_prices.size());
  for (std::size_t i = 0; i < leaf_prices.size(); ++i)
    traversal[i] = std::max(sah.traversal_cost, leaf_prices[i] * sah.intersection_cost);
  std::vector<BinaryBvh> trees = build_binned_sah_costs(local, sah, traversal);
  if (builder_reinserts(builder.kind))
    for (std::size_t i = 0; i < trees.size(); ++i) {
      SahOptions leaf_sah = sah;
      leaf_sah.traversal_cost = traversal[i];
      trees[i] = reinsert_optimize(trees[i], leaf_sah, builder.reinsert);
    }
  // Collapsed here, on the build's threads, instead of at the append, which runs on one
  // (perf: a tenth of auto's build of the bear, on one thread, for its four shapes).
  for (const BinaryBvh& t : trees) {
    ClusterBlas::Tree& tree = out.trees.emplace_back();
    tree.root_box = t.nodes[0].box;
    try {
      tree.nodes = collapse_bvh(t, c.members, ps.features.nodes);
    } catch (const Error& e) {
      tree.error = e.what(); // thrown by the append of this price, in cluster order
    }
  }
  return out;
}

} // namespace

Affine3 realised_object_to_local(const Mat3x4f& world_to_local, const Mat3x4f& frame_world_to_object) {
  return compose(from_mat3x4f(world_to_local), inverse(from_mat3x4f(frame_world_to_object)));
}

std::vector<ClusterBlas> build_cluster_blases(const Scene& scene, int geom, const std::vector<Cluster>& clusters,
                                              const std::vector<int>& scene_insts, const SahOptions& sah,
                                              std::span<const double> leaf_prices, const BuilderOptions& builder,
                                              const PackedScene& ps, const ClusterHulls* hulls) {
  const Geometry& g = scene.geometries.at(std::size_t(geom));
  for (const Cluster& c : clusters)
    if (c.members.empty()) throw Error("cluster: an empty cluster in geometry " + std::to_string(geom));
  if (hulls && !hulls_match(*hulls, clusters))
    throw Error("cluster: member hulls that are not the clusters' in geometry " + std::to_string(geom));
  // Every cluster's local boxes and binary BLAS at once, each in its own slot.
  std::vector<ClusterBlas> built(clusters.size());
  parallel_chunks(clusters.size(), 1, [&](std::size_t c0, std::size_t c1) {
    std::vector<BallHull> read;
    for (std::size_t ci = c0; ci < c1; ++ci)
      built[ci] = build_cluster(scene, g, clusters[ci], scene_insts, sah, leaf_prices, builder, ps,
                                hulls ? &(*hulls)[ci] : nullptr, read);
  });
  return built;
}

void append_cluster_instances(const Scene& scene, int geom, const std::vector<Cluster>& clusters,
                              const std::vector<int>& scene_insts, const SahOptions& sah, double leaf_price,
                              const BuilderOptions& builder, PackedScene& ps, HugePageVector<Aabb>& inst_boxes,
                              const ClusterHulls* hulls) {
  const double prices[] = {leaf_price};
  append_cluster_instances(geom, clusters, scene_insts,
                           build_cluster_blases(scene, geom, clusters, scene_insts, sah, prices, builder, ps, hulls), 0,
                           ps, inst_boxes);
}

void append_cluster_instances(int geom, const std::vector<Cluster>& clusters,
                              const std::vector<int>& scene_insts, const std::vector<ClusterBlas>& built,
                              std::size_t price_index, PackedScene& ps, HugePageVector<Aabb>& inst_boxes) {
  if (built.size() != clusters.size())
    throw Error("cluster: " + std::to_string(built.size()) + " cluster BLAS for " + std::to_string(clusters.size()) +
                " clusters in geometry " + std::to_string(geom));
  // Where each cluster's nodes and references go, in cluster order; then all of them
  // written there at once.
  std::vector<std::size_t> node_at(clusters.size()), ref_at(clusters.size());
  std::size_t nodes = 0, refs = 0;
  for (std::size_t ci = 0; ci < clusters.size(); ++ci) {
    if (!built[ci].error.empty()) throw Error(built[ci].error + std::to_string(geom) + " is not finite");
    if (price_index >= built[ci].trees.size())
      throw Error("cluster: leaf price " + std::to_string(price_index) + " of " +
                  std::to_string(built[ci].trees.size()) + " built in geometry " + std::to_string(geom));
    if (!built[ci].trees[price_index].error.empty()) throw Error(built[ci].trees[price_index].error);
    const CollapsedBvh& tree = built[ci].trees[price_index].nodes;
    node_at[ci] = nodes;
    ref_at[ci] = refs;
    nodes += collapsed_nodes(tree);
    refs += tree.refs.size();
  }
  const std::size_t node_end = ps.node_count(), ref_end = ps.refs.size();
  grow_node_arrays(ps, nodes, refs);
  std::vector<WideBvhInfo> infos(clusters.size());
  parallel_chunks(clusters.size(), 64, [&](std::size_t c0, std::size_t c1) {
    for (std::size_t ci = c0; ci < c1; ++ci)
      infos[ci] = place_collapsed(built[ci].trees[price_index].nodes, ps, node_end + node_at[ci], ref_end + ref_at[ci]);
  });
  // The instances and sums, cluster by cluster, in order.
  for (std::size_t ci = 0; ci < clusters.size(); ++ci) {
    const Cluster& c = clusters[ci];
    const std::vector<Mat3x4f>& stored = built[ci].stored;
    const ClusterBlas::Tree& tree = built[ci].trees[price_index];
    const WideBvhInfo& info = infos[ci];
    ps.stats.blas_references += tree.nodes.refs.size(); // each leaf reference once
    ps.stats.blas_primitives += c.members.size();
    ps.stats.blas_nodes += info.nodes;
    ps.stats.blas_leaves += info.leaves;
    ps.stats.blas_sah_cost += info.sah_cost;
    ps.features.blas_stack.entries = std::max(ps.features.blas_stack.entries, info.kernel_stack);
    const Aabb& cluster_local = tree.root_box;
    const std::size_t members = c.members.size();
    for (std::size_t k = 0; k < scene_insts.size(); ++k) {
      int si = scene_insts[k];
      const Affine3& l2w = built[ci].local_to_world[k];
      // TLAS box: the members' exact world boxes, clipped by the world image of the
      // cluster's local box (tighter for clusters diagonal to the world axes).
      const Aabb& exact = built[ci].exact[k];
      for (std::size_t m = 0; m < members; ++m) {
        const ClusterBlas::MemberAreas& a = built[ci].member_areas[k * members + m];
        ps.stats.aabb_area += a.aabb;
        ps.stats.obb_area += a.obb;
      }
      Aabb corners;
      for (int i = 0; i < 8; ++i)
        corners.grow(l2w.apply_point({i & 1 ? cluster_local.hi.x : cluster_local.lo.x,
                                      i & 2 ? cluster_local.hi.y : cluster_local.lo.y,
                                      i & 4 ? cluster_local.hi.z : cluster_local.lo.z}));
      kernel::Instance inst{};
      std::memcpy(inst.world_to_object, stored[k].data(), sizeof(inst.world_to_object));
      inst.blas_root = info.root;
      inst.geom = geom;
      inst.prim = MASQ_INST_CLUSTER;
      inst.scene_inst = si;
      ps.instances.push_back(inst);
      ps.instance_object_to_world.push_back(to_mat3x4f(l2w));
      inst_boxes.push_back(Aabb::intersect(exact, corners));
      ps.stats.clusters += 1;
      ps.stats.max_depth = std::max(ps.stats.max_depth, info.depth);
    }
  }
}

} // namespace masq
