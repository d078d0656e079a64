// Builds the two-level structure of a scene for one method.
//  ref:  one BLAS per geometry over its primitives' AABBs; one TLAS entry per scene
//        instance (the reference method of Wald et al. 2020).
//  masq: every capsule, round cone, sphere and curve becomes a TLAS entry whose
//        transform maps the unit box onto its OBB (the masquerade); triangle
//        geometries keep their BLAS, since a triangle's OBB is flat and a map of the
//        unit box onto it would be singular.
//  cluster, auto: see bvh/twolevel/method_plan.h and docs/methods.md.
#pragma once
#include "bvh/binary/binned_sah.h"
#include "bvh/binary/builder.h"
#include "bvh/twolevel/method_plan.h"
#include "bvh/bounds/obb.h"
#include "bvh/nodes/node_frame.h"
#include "bvh/packed_scene.h"
#include "scenes/scene.h"
#include <array>
#include <string>
#include <vector>

namespace masq {

// How method auto decides: build ref, masq, cluster and its per-cluster mix whole and
// keep the one bvh/twolevel/structure_cost.h prices lowest, or build the mix alone (cheaper to
// build; the tests use it to exercise TLASes that mix every instance kind).
enum class AutoSelect { WholeStructure, MixOnly };

struct AccelOptions {
  SahOptions sah;
  BuilderOptions builder;               // binary BVH builder (bvh/binary/builder.h); sah by default
  CurveObb curve_obb = CurveObb::Tight; // masq: how curve OBBs are oriented
  Mode mode = Mode::Robust;             // kernel intersectors and box test
  int curve_iters = 24;                 // phantom iteration limit (1..64; 24: see docs/robustness.md)
  CurveIsect curve_isect = CurveIsect::Phantom; // the cubic-curve intersector
  ClusterOptions cluster;               // cluster, auto: cluster size and orientation classes
  CostPrices prices;                    // auto: the whole-structure cost model's prices
  AutoSelect auto_select = AutoSelect::WholeStructure;
  NodeFormat nodes = NodeFormat::W4;    // BVH node layout of the TLAS and every BLAS
  // o4: a BLAS node is rotated when that costs at most this fraction of its axis-aligned
  // children's SAH (bvh/nodes/node_frame.h); +inf rotates every node.
  double oriented_gain = kOrientedGain;
  MasqInstances masq_instances = MasqInstances::Compact;
  // Occlusion queries' order over a BLAS node's hit inner children (KernelFeatures::
  // blas_starts_last; kernels/child_order.h).
  BlasOcclusion blas_occlusion = BlasOcclusion::Nearest;
  // Compact entries name their (geometry, scene instance) pair by a 16-bit owner index;
  // the masquerade primitives of pairs beyond this many get 64-byte Instances (tests
  // lower it; above MASQ_MAX_OWNERS it has no effect).
  int masq_owner_limit = MASQ_MAX_OWNERS;
  // Host build threads (bvh/binary/parallel.h): 0 every hardware thread, 1 serial. The
  // structure is the same, bit for bit, with any count (docs/builders.md).
  int build_threads = 0;
};

PackedScene build_accel(const Scene& scene, Method method, const AccelOptions& opt = {});

// auto's candidates, each built whole: ref, then, when the scene has other primitives
// than triangles, masq, cluster (of auto_cluster_shapes the shape the model prices
// lowest) and the per-cluster mix (PackedScene::method Auto), unless the mix's plan is
// ref's (mix_is_ref). A mesh has ref alone.
struct AutoCandidates {
  std::vector<PackedScene> built;
  std::array<double, 4> costs{}; // each one's model cost, indexed by Method (a mesh: ref's in all)
  std::vector<double> cluster_shape_costs; // each cluster shape's model cost (auto_cluster_shapes' order)
  // The mix's plan kept every primitive in the BLAS, so the mix is ref's structure: it
  // is not in `built` (it could not be kept over the earlier ref), and costs has ref's
  // cost for it.
  bool mix_is_ref = false;
  double seconds = 0;            // host time to build them all
};
AutoCandidates build_auto_candidates(const Scene& scene, const AccelOptions& opt);
// The index into c.built the structure cost model keeps (build_accel's auto rule;
// docs/methods.md). bench/auto_pilot.h chooses by measurement instead.
std::size_t model_choice(const AutoCandidates& c);
// Makes `kept` (one of c.built, or a copy) auto's structure: method Auto, the candidate
// in stats.auto_choice, every candidate's cost in stats.auto_candidates, and the build
// time of all of them.
void mark_as_auto(PackedScene& kept, const AutoCandidates& c);

// The cluster shapes auto builds for its cluster candidate: the given one, then with
// kAutoLargeCluster members and with leaf price 1 (one member per leaf), and both.
inline constexpr int kAutoLargeCluster = 256;
std::vector<ClusterOptions> auto_cluster_shapes(const ClusterOptions& given);

} // namespace masq
