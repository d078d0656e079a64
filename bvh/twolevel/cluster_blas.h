// The GPU side of oriented clusters: one BLAS per cluster over its members' bounds in
// the cluster's local frame, shared by every scene instance of the geometry, and one
// TLAS entry per (scene instance, cluster) whose transform maps the world into that
// frame (kernels/layout.h: MASQ_INST_CLUSTER).
#pragma once
#include "bvh/binary/binned_sah.h"
#include "bvh/binary/builder.h"
#include "bvh/twolevel/clusters.h"
#include "bvh/packed_scene.h"
#include "scenes/scene.h"
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
// `leaf_price`: ClusterOptions::leaf_price.
void append_cluster_instances(const Scene& scene, int geom, const std::vector<Cluster>& clusters,
                              const std::vector<int>& scene_insts, const SahOptions& sah, double leaf_price,
                              const BuilderOptions& builder, PackedScene& ps, HugePageVector<Aabb>& inst_boxes);

} // namespace masq
