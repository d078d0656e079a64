// The whole-structure cost model (bvh/twolevel/structure_cost.h) and method auto's choice by it:
// exact values on one-primitive scenes, the choice on bundles whose winner is clear
// (axis-aligned: ref; dense and tilted: an oriented structure), and that auto's arrays
// are byte for byte those of the candidate it reports keeping.
#include "bvh/twolevel/build_accel.h"
#include "bvh/twolevel/structure_cost.h"
#include "scenes/generators.h"
#include "scenes/strand_generators.h"
#include <gtest/gtest.h>
#include <algorithm>
#include <cstring>

using namespace masq;

namespace {

Scene one_capsule() {
  Geometry g;
  g.type = PrimType::Capsule;
  g.capsules.push_back({{0.0f, 0.0f, 0.0f}, {1.0f, 0.0f, 0.0f}, 0.1f});
  Scene s;
  s.name = "one capsule";
  s.geometries.push_back(g);
  s.instances.push_back({0, {}});
  return s;
}

Scene bundle(int count, float radius, double tilt) {
  BundleParams p;
  p.count = count;
  p.radius = radius;
  p.tilt_deg = tilt;
  Scene s;
  s.name = "bundle";
  s.geometries.push_back(make_bundle(p));
  s.instances.push_back({0, {}});
  return s;
}

template <class T, class A, class B> bool same_bytes(const std::vector<T, A>& a, const std::vector<T, B>& b) {
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}

// The model's price of a plain build (auto's builds carry theirs in stats.model_cost).
double priced(const PackedScene& ps, const AccelOptions& opt = {}) { return structure_cost(ps, opt.prices).total; }

} // namespace

TEST(StructureCost, OneCapsuleUnderRefIsRootVisitPlusOneCall) {
  // Single BLAS, no TLAS stage: the root node is visited by every ray reaching the
  // scene box, and its one leaf box is the scene box: 1 node visit + 1 capsule call.
  PackedScene ps = build_accel(one_capsule(), Method::Ref);
  ASSERT_TRUE(ps.features.single_blas);
  CostPrices prices;
  StructureCost c = structure_cost(ps, prices);
  EXPECT_NEAR(c.nodes, 1.0, 1e-12);
  EXPECT_NEAR(c.transforms, 0.0, 1e-12);
  EXPECT_NEAR(c.isects, 1.0, 1e-6);
  EXPECT_NEAR(c.total, prices.node + prices.isect, 1e-6);
  EXPECT_EQ(c.triangles, 0.0);
  EXPECT_EQ(ps.stats.model_cost, 0.0); // a plain build is not priced
  EXPECT_EQ(priced(ps), c.total);
}

TEST(StructureCost, OneCapsuleUnderMasqCallsOnlyInsideItsObb) {
  // An axis-aligned capsule's OBB is its AABB: one TLAS visit, one transform, and the
  // call whenever the unit box is hit (probability 1 here).
  PackedScene ps = build_accel(one_capsule(), Method::Masq);
  StructureCost c = structure_cost(ps, CostPrices{});
  EXPECT_NEAR(c.nodes, 1.0, 1e-12);
  EXPECT_NEAR(c.transforms, 1.0, 1e-6);
  EXPECT_NEAR(c.isects, 1.0, 1e-3);
}

TEST(StructureCost, PricesScaleTheirTermsOnly) {
  PackedScene ps = build_accel(bundle(200, 0.004f, 30.0), Method::Masq);
  StructureCost a = structure_cost(ps, CostPrices{1.0, 1.0, 1.0});
  StructureCost b = structure_cost(ps, CostPrices{2.0, 3.0, 5.0});
  EXPECT_DOUBLE_EQ(a.nodes, b.nodes);
  EXPECT_NEAR(b.total, 2.0 * a.nodes + 3.0 * a.transforms + 5.0 * a.isects, 1e-9 * b.total);
}

TEST(StructureCost, CurvesCostMoreCallsThanCapsules) {
  EXPECT_GT(isect_type_factor(MASQ_PRIM_CURVE), isect_type_factor(MASQ_PRIM_CAPSULE));
}

TEST(AutoSelect, AxisAlignedBundleKeepsRef) {
  // Tilt 0: every OBB is its AABB; nothing beats ref by the margin.
  PackedScene ps = build_accel(bundle(1000, 0.002f, 0.0), Method::Auto);
  EXPECT_EQ(ps.stats.auto_choice, Method::Ref);
}

TEST(AutoSelect, DenseTiltedBundleLeavesRef) {
  // The paper's worst case for AABBs: 1000 strands at 45 degrees. Measured: cluster and
  // masq several times faster than ref on every backend (docs/methods.md).
  PackedScene ps = build_accel(bundle(1000, 0.002f, 45.0), Method::Auto);
  EXPECT_NE(ps.stats.auto_choice, Method::Ref);
  const auto& k = ps.stats.auto_candidates;
  EXPECT_LT(ps.stats.model_cost, 0.5 * k[std::size_t(Method::Ref)]);
}

TEST(AutoSelect, KeepsTheCandidatesBytes) {
  for (double tilt : {0.0, 15.0, 45.0}) {
    Scene s = bundle(300, 0.003f, tilt);
    PackedScene a = build_accel(s, Method::Auto);
    ASSERT_EQ(a.method, Method::Auto);
    Method kept = a.stats.auto_choice;
    AccelOptions mix;
    mix.auto_select = AutoSelect::MixOnly;
    AccelOptions shape; // the cluster candidate's shape auto kept
    shape.cluster.max_size = a.stats.cluster_size;
    shape.cluster.leaf_price = a.stats.cluster_leaf_price;
    PackedScene c = kept == Method::Auto ? build_accel(s, Method::Auto, mix) : build_accel(s, kept, shape);
    SCOPED_TRACE("tilt " + std::to_string(tilt) + " kept " + method_name(kept));
    EXPECT_TRUE(same_bytes(a.nodes, c.nodes));
    EXPECT_TRUE(same_bytes(a.refs, c.refs));
    EXPECT_TRUE(same_bytes(a.instances, c.instances));
    EXPECT_TRUE(same_bytes(a.masq_instances, c.masq_instances));
    EXPECT_TRUE(same_bytes(a.masq_owners, c.masq_owners));
    EXPECT_EQ(a.tlas_root, c.tlas_root);
    EXPECT_EQ(a.stats.model_cost, a.stats.auto_candidates[std::size_t(kept)]);
  }
}

TEST(AutoSelect, TrianglesShareIsCountedApart) {
  // The default scene's ground plane costs the same in every candidate.
  StructureCost c = structure_cost(build_accel(make_default_scene(), Method::Ref), CostPrices{});
  EXPECT_GT(c.triangles, 0.0);
  EXPECT_LT(c.triangles, c.total);
}

TEST(AutoSelect, MeshHasOnlyRefsCandidate) {
  // Triangles stay in a BLAS under every method, so auto builds ref's structure once.
  Scene s;
  s.name = "mesh";
  s.geometries.push_back(make_random_mesh(200, 1.0, 5));
  s.instances.push_back({0, {}});
  PackedScene a = build_accel(s, Method::Auto);
  PackedScene r = build_accel(s, Method::Ref);
  EXPECT_EQ(a.stats.auto_choice, Method::Ref);
  EXPECT_TRUE(same_bytes(a.nodes, r.nodes));
  EXPECT_TRUE(same_bytes(a.instances, r.instances));
  for (double c : a.stats.auto_candidates) EXPECT_EQ(c, priced(r));
}

TEST(AutoSelect, ClusterShapesAreDistinctAndStartWithTheGivenOne) {
  ClusterOptions given;
  given.max_size = 16;
  given.leaf_price = 3.0;
  std::vector<ClusterOptions> shapes = auto_cluster_shapes(given);
  ASSERT_EQ(shapes.size(), 4u);
  EXPECT_EQ(shapes[0].max_size, 16);
  EXPECT_EQ(shapes[0].leaf_price, 3.0);
  for (std::size_t i = 0; i < shapes.size(); ++i)
    for (std::size_t j = i + 1; j < shapes.size(); ++j)
      EXPECT_FALSE(shapes[i].max_size == shapes[j].max_size && shapes[i].leaf_price == shapes[j].leaf_price);
  given.max_size = kAutoLargeCluster;
  given.leaf_price = 1.0;
  EXPECT_EQ(auto_cluster_shapes(given).size(), 1u); // nothing else to try
}

TEST(AutoSelect, KeepsTheCheapestClusterShape) {
  // The dense tilted bundle: every member parallel, so auto keeps a cluster, in the shape
  // the model prices lowest among those it tries, and reports that shape.
  Scene s = bundle(1000, 0.002f, 45.0);
  PackedScene a = build_accel(s, Method::Auto);
  ASSERT_EQ(a.stats.auto_choice, Method::Cluster);
  double cheapest = 0;
  for (const ClusterOptions& shape : auto_cluster_shapes(AccelOptions{}.cluster)) {
    AccelOptions o;
    o.cluster = shape;
    PackedScene c = build_accel(s, Method::Cluster, o);
    EXPECT_EQ(c.stats.cluster_size, shape.max_size);
    EXPECT_GE(priced(c, o), a.stats.model_cost);
    if (cheapest == 0 || priced(c, o) < cheapest) cheapest = priced(c, o);
  }
  EXPECT_EQ(a.stats.model_cost, cheapest);
  EXPECT_EQ(a.stats.auto_candidates[std::size_t(Method::Cluster)], cheapest);
}

// auto's candidates share the clusterings of one cluster size (its cluster shapes of one
// size, and the mix): each candidate must still be, byte for byte, what its method
// builds alone in the shape it kept.
TEST(AutoSelect, SharedClusteringsGiveEachCandidateItsOwnBuild) {
  HairParams hp;
  hp.strands = 600;
  hp.points = 8;
  hp.type = PrimType::Capsule;
  int mixes_as_ref = 0; // mixes that chose ref everywhere: ref's structure, not a candidate of their own
  for (const Scene& s : {bundle(400, 0.002f, 45.0), make_hair_scene(hp)}) {
    AutoCandidates c = build_auto_candidates(s, {});
    ASSERT_EQ(c.built.size(), c.mix_is_ref ? 3u : 4u);
    if (c.mix_is_ref) {
      // The mix built alone is ref's structure, and its cost ref's, to the bit.
      ++mixes_as_ref;
      AccelOptions o;
      o.auto_select = AutoSelect::MixOnly;
      PackedScene alone = build_accel(s, Method::Auto, o);
      const PackedScene& ref = c.built[0];
      ASSERT_EQ(ref.method, Method::Ref);
      SCOPED_TRACE(s.name + " mix that is ref");
      EXPECT_EQ(alone.stats.masq_prims + alone.stats.clusters, 0u);
      EXPECT_EQ(std::memcmp(&alone.stats.model_cost, &c.costs[std::size_t(Method::Auto)], sizeof(double)), 0);
      EXPECT_EQ(std::memcmp(&ref.stats.model_cost, &c.costs[std::size_t(Method::Auto)], sizeof(double)), 0);
      ASSERT_EQ(alone.nodes.size(), ref.nodes.size());
      EXPECT_EQ(std::memcmp(alone.nodes.data(), ref.nodes.data(), alone.nodes.size() * sizeof(alone.nodes[0])), 0);
      EXPECT_EQ(alone.refs, ref.refs);
      EXPECT_FALSE(std::any_of(c.built.begin(), c.built.end(),
                               [](const PackedScene& p) { return p.method == Method::Auto; }));
    }
    for (const PackedScene& cand : c.built) {
      AccelOptions o;
      o.cluster.max_size = cand.stats.cluster_size;
      o.cluster.leaf_price = cand.stats.cluster_leaf_price;
      if (cand.method == Method::Auto) o.auto_select = AutoSelect::MixOnly;
      PackedScene alone = build_accel(s, cand.method, o);
      SCOPED_TRACE(s.name + " " + method_name(cand.method));
      const double alone_cost = cand.method == Method::Auto ? alone.stats.model_cost : priced(alone, o);
      EXPECT_EQ(std::memcmp(&alone_cost, &cand.stats.model_cost, sizeof(double)), 0);
      ASSERT_EQ(alone.nodes.size(), cand.nodes.size());
      EXPECT_EQ(std::memcmp(alone.nodes.data(), cand.nodes.data(), alone.nodes.size() * sizeof(alone.nodes[0])), 0);
      EXPECT_EQ(alone.refs, cand.refs);
      ASSERT_EQ(alone.instances.size(), cand.instances.size());
      EXPECT_EQ(std::memcmp(alone.instances.data(), cand.instances.data(),
                            alone.instances.size() * sizeof(alone.instances[0])),
                0);
      EXPECT_EQ(alone.tlas_leaf_order, cand.tlas_leaf_order);
    }
  }
  EXPECT_GE(mixes_as_ref, 1); // the hair's mix: checked against ref's structure above
}

// The cluster shapes of one size take their BLAS from one build for every leaf price
// (bvh/twolevel/cluster_blas.h, build_cluster_blases): each shape's model cost, kept or
// not, must be the one its build alone prices, to the bit.
TEST(AutoSelect, EveryClusterShapeIsItsOwnBuild) {
  HairParams hp;
  hp.strands = 600;
  hp.points = 8;
  hp.type = PrimType::Capsule;
  for (const Scene& s : {bundle(400, 0.002f, 45.0), make_hair_scene(hp)})
    for (Builder b : all_builders()) {
      if (b != Builder::Sah && !builder_reinserts(b)) continue; // the plain trees, and the refined ones
      AccelOptions given;
      given.builder.kind = b;
      AutoCandidates c = build_auto_candidates(s, given);
      const std::vector<ClusterOptions> shapes = auto_cluster_shapes(given.cluster);
      ASSERT_EQ(c.cluster_shape_costs.size(), shapes.size());
      for (std::size_t k = 0; k < shapes.size(); ++k) {
        AccelOptions o = given;
        o.cluster = shapes[k];
        const double alone = priced(build_accel(s, Method::Cluster, o), o);
        SCOPED_TRACE(s.name + " " + builder_name(b) + " shape " + std::to_string(shapes[k].max_size) + "/" +
                     std::to_string(shapes[k].leaf_price));
        EXPECT_EQ(std::memcmp(&alone, &c.cluster_shape_costs[k], sizeof(double)), 0);
      }
    }
}
