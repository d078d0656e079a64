// The GPU side of oriented clusters: one BLAS per cluster over its members' bounds in
// the cluster's local frame, shared by every scene instance of the geometry, and one
// TLAS entry per (scene instance, cluster) whose transform maps the world into that
// frame (kernels/layout.h: MASQ_INST_CLUSTER).
#pragma once
#include "bvh/binary/binned_sah.h"
#include "bvh/binary/builder.h"
#include "bvh/bounds/prim_bounds.h"
#include "bvh/nodes/wide_bvh.h"
#include "bvh/twolevel/clusters.h"
#include "bvh/packed_scene.h"
#include "scenes/scene.h"
#include <span>
#include <string>
#include <vector>

namespace masq {

// The map the kernel realises from a scene instance's object space to a cluster's
// local frame: the stored fp32 world-to-local matrix after the inverse of the stored
// fp32 world-to-object frame (the intersector runs in that frame), in double.
Affine3 realised_object_to_local(const Mat3x4f& world_to_local, const Mat3x4f& frame_world_to_object);

// Appends the BLAS and TLAS entries of geometry `geom`'s clusters, placed by each scene
// instance in `scene_insts` (indices into scene.instances and ps.frames), to ps; the
// entries' world boxes go to inst_boxes. The local boxes contain every member's hull
// under realised_object_to_local for every one of those instances, rounded outward.
// The cluster BLAS get no spatial splits (their members are parallel and side by side,
// so their local boxes barely overlap; and a piece would have to be clipped under every
// instance's realised map): reinsertion only, where the builder has it.
// `leaf_price`: ClusterOptions::leaf_price. `hulls`: the clusters' member hulls
// (make_clusters), when the caller has them; nullptr: read here.
void append_cluster_instances(const Scene& scene, int geom, const std::vector<Cluster>& clusters,
                              const std::vector<int>& scene_insts, const SahOptions& sah, double leaf_price,
                              const BuilderOptions& builder, PackedScene& ps, HugePageVector<Aabb>& inst_boxes,
                              const ClusterHulls* hulls = nullptr);

// One cluster's BLAS before its nodes are appended: per scene instance its
// world-to-local matrix as stored, that matrix's inverse and its members' exact world
// boxes together, per (instance, member) the member's world AABB and OBB areas, and per
// leaf price a tree (over the members' local boxes under every realised map) collapsed
// into the packed scene's node format.
struct ClusterBlas {
  struct MemberAreas {
    double aabb = 0, obb = 0;
  };
  struct Tree {
    CollapsedBvh nodes;
    Aabb root_box;     // the members' local boxes together
    std::string error; // the collapse failed (masq::Error's message; nodes empty)
  };
  std::vector<Mat3x4f> stored;
  std::vector<Affine3> local_to_world;
  std::vector<Aabb> exact;
  std::vector<MemberAreas> member_areas; // instance k, member m: [k * members + m]
  std::vector<Tree> trees;
  std::string error; // set (and the rest incomplete) when a local box is not finite
};

// Every cluster's BLAS of geometry `geom` for each of `leaf_prices` (their trees from
// one binning: build_binned_sah_costs), on all threads, collapsed into ps's node format
// there too: auto's cluster shapes of one size differ in the leaf price alone, and
// build theirs once. `hulls`: as append_cluster_instances takes them.
std::vector<ClusterBlas> build_cluster_blases(const Scene& scene, int geom, const std::vector<Cluster>& clusters,
                                              const std::vector<int>& scene_insts, const SahOptions& sah,
                                              std::span<const double> leaf_prices, const BuilderOptions& builder,
                                              const PackedScene& ps, const ClusterHulls* hulls = nullptr);

// append_cluster_instances with the clusters' BLAS built (`built[i]` the BLAS of
// clusters[i], from build_cluster_blases with the same clusters, instances and frames):
// the tree of leaf price `price_index`. Throws masq::Error when they do not match.
void append_cluster_instances(int geom, const std::vector<Cluster>& clusters,
                              const std::vector<int>& scene_insts, const std::vector<ClusterBlas>& built,
                              std::size_t price_index, PackedScene& ps, HugePageVector<Aabb>& inst_boxes);

} // namespace masq
