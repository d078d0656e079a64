// A scene built for tracing with one method: the GPU arrays every compute backend
// uploads as-is (layouts from kernels/layout.h), plus what the rayquery backend needs
// to hand the same scene to the driver's own acceleration-structure builder.
#pragma once
#include "bvh/mat3x4f.h"
#include "bvh/options.h"
#include "kernels/layout.h"
#include "kernels/variant_table.h"
#include "scenes/kernel_prims.h"
#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace masq {

// The BVH node layouts of kernels/layout.h (NodeFormat: bvh/options.h, docs/kernels.md,
// "Node formats"). The rayquery backend ignores them.
int node_format_id(NodeFormat f);            // MASQ_NODES_* of kernels/layout.h
std::size_t node_format_bytes(NodeFormat f); // one node

// The worst-case number of entries one traversal stack holds over a scene's trees, as
// the kernels push them (bvh/nodes/wide_bvh.h, WideBvhInfo::kernel_stack); the kernels'
// stack is sized from it (host/stack_size.h). Unknown (a scene not from the builders):
// the largest stack.
struct StackNeed {
  int entries = MASQ_STACK_MAX;
  const char* tree = "traversal"; // which walk, for errors
  bool operator==(const StackNeed& o) const { return entries == o.entries; }
};

// The kernel variant a scene needs: the primitive types present (the others are
// compiled out), the intersector mode, the phantom-curve iteration limit and the
// traversal stacks' sizes. Every backend maps this onto its variant mechanism (spec
// constants, -D, C++ TUs).
struct KernelFeatures {
  // Per MASQ_PRIM_* id: the scene holds that type (its MASQ_HAVE_* switch; the variant
  // table's rows read prims[MASQ_PRIM_*], so a new type adds no member here).
  std::array<bool, MASQ_PRIM_TYPE_COUNT> prims{};
  Mode mode = Mode::Robust;
  int curve_iters = 24;
  CurveIsect curve_isect = CurveIsect::Phantom;
  bool single_blas = false; // one BLAS instance, identity transform: no TLAS stage
  // Occlusion queries take the TLAS boxes the ray starts in last (kernels/child_order.h):
  // set where the TLAS holds masquerade entries, one primitive a box.
  bool tlas_starts_last = false;
  // Occlusion queries take a BLAS node's hit inner children the ray starts in last
  // (AccelOptions::blas_occlusion, BlasOcclusion::StartsLast).
  bool blas_starts_last = false;
  NodeFormat nodes = NodeFormat::W4;
  StackNeed tlas_stack{MASQ_STACK_MAX, "TLAS"}; // the TLAS walk (trace_closest)
  StackNeed blas_stack{MASQ_STACK_MAX, "BLAS"}; // every BLAS walk (traverse_blas; the bv kernels' one tree)
  bool operator==(const KernelFeatures&) const = default;
};

struct BuildStats {
  double sah_cost = 0;         // TLAS: traversal 1 per wide node, 1 per instance reference
  double blas_sah_cost = 0;    // sum over BLAS, each relative to its own root box
  std::size_t tlas_nodes = 0;  // wide nodes
  std::size_t blas_nodes = 0;  // wide nodes, all BLAS
  std::size_t node_bytes = 0;  // TLAS and BLAS nodes in the scene's node format
  std::size_t oriented_nodes = 0; // o4: nodes with a rotated frame (the others axis aligned)
  std::size_t tlas_leaves = 0;
  std::size_t blas_leaves = 0;
  std::size_t instances = 0;   // TLAS entries
  int max_depth = 0;           // wide levels, TLAS + BLAS
  // masq: summed surface areas of the masquerade OBBs and of the same primitives'
  // exact world AABBs (the masquerade paper's Fig. 9 compares the two).
  // cluster/auto: the same for the members of clusters (their local boxes' world areas).
  double obb_area = 0, aabb_area = 0;
  std::size_t clusters = 0;     // cluster instances (cluster and auto)
  // The cluster shape the structure was built with (ClusterOptions max_size and
  // leaf_price; auto tries several, bvh/twolevel/build_accel.cpp).
  int cluster_size = 0;
  double cluster_leaf_price = 0;
  std::size_t masq_prims = 0;   // masquerade instances (masq and auto)
  // Expected work per ray of this structure under the auto prices (bvh/twolevel/structure_cost.h),
  // filled by auto's builds (its candidates, the one it kept, and the mix alone); 0 for a
  // plain ref, masq or cluster build, whose structure_cost() the caller asks for instead.
  double model_cost = 0;
  double model_triangles = 0; // its share spent in triangle geometries
  // auto: the candidate it kept (ref, masq, cluster, or Auto for its per-cluster mix)
  // and each candidate's model_cost, indexed by Method (Ref, Masq, Cluster, Auto = mix).
  Method auto_choice = Method::Auto;
  std::array<double, 4> auto_candidates{};
  // Leaf references and primitives over every BLAS (cluster BLAS included): their
  // ratio is 1 unless spatial splits (builder sbvh) put a primitive in several leaves.
  std::size_t blas_references = 0, blas_primitives = 0;
  double build_seconds = 0;
};

// The primitive arrays (triangles, capsules, ...: one per PRIM row of the scene array
// table) are the KernelPrimArrays base, filled by the scenes layer's rows (pack).
struct PackedScene : KernelPrimArrays {
  Method method = Method::Ref;
  Builder builder = Builder::Sah;
  // The arrays that grow with the scene are HugePageVectors (scenes/huge_page_vector.h:
  // on huge pages from 2 MiB, which a build of the bear halves the page faults of).
  // TLAS and all BLAS nodes: one of the four arrays, by features.nodes (the others empty).
  HugePageVector<kernel::WideNode> nodes;        // w4
  HugePageVector<kernel::WideNode8> nodes8;      // w8
  HugePageVector<kernel::QuantNode8> qnodes;     // q8
  HugePageVector<kernel::OrientedNode4> onodes;  // o4
  // Leaf references: prim ids (BLAS); TLAS entries: r >= 0 is instances[r], r < 0 the
  // compact masquerade entry masq_instances[~r] (kernels/layout.h, MasqInstance).
  HugePageVector<std::int32_t> refs;
  HugePageVector<kernel::Instance> instances;
  HugePageVector<kernel::MasqInstance> masq_instances; // AccelOptions::masq_instances == compact
  std::vector<kernel::MasqOwner> masq_owners;       // their (geometry, scene instance) pairs
  std::vector<kernel::Frame> frames;     // one per scene instance
  std::vector<kernel::Geometry> geoms;
  std::int32_t tlas_root = -1;
  KernelFeatures features;

  // For the rayquery backend and the host's own walks. TLAS entry ids: e < instances.size()
  // is instances[e], the others masq_instances[e - instances.size()] (see tlas_ref).
  std::vector<Mat3x4f> frame_object_to_world;    // per scene instance
  HugePageVector<Mat3x4f> instance_object_to_world; // per TLAS entry (masquerade: unit box -> world)
  HugePageVector<std::int32_t> tlas_leaf_order;     // TLAS entry ids in leaf order (submission order)
  // Per geometry: its primitive ids in BLAS leaf order (submission order for the driver).
  std::vector<std::vector<std::int32_t>> geometry_leaf_order;

  BuildStats stats;

  // The node array of the scene's format, as the kernels' node binding receives it.
  const void* node_data() const;
  std::size_t node_count() const;
  std::size_t node_bytes() const;
  std::size_t acceleration_bytes() const; // nodes + refs + instances + compact entries + owners + frames

  // TLAS entries: Instances, then compact masquerade entries.
  std::size_t tlas_entry_count() const { return instances.size() + masq_instances.size(); }
  std::int32_t tlas_ref(std::size_t entry) const; // the TLAS leaf reference of an entry
  std::size_t tlas_entry(std::int32_t ref) const; // and back
  // (An entry as a full Instance record: tlas_entry_instance in bvh/nodes/compact_instance.h.)
  std::size_t primitive_bytes() const;    // geoms + all primitive arrays
};

} // namespace masq
