// Oriented clusters (method cluster) and the cost-model choice (method auto):
// partition invariants, conservative local boxes under the stored fp32 transforms
// (checked in double), no false culls far from the origin, and the effect on the
// default scene (fewer intersector calls than ref, memory within 1.2x of ref).
#include "bvh/twolevel/build_accel.h"
#include "bvh/twolevel/cluster_blas.h"
#include "host/backend.h"
#include "masq/error.h"
#include "scenes/camera.h"
#include "scenes/generators.h"
#include <gtest/gtest.h>
#include <cmath>
#include <cstring>
#include <random>
#include <set>
#include "tests/random_affine.h"

using namespace masq;
using masq::test::random_affine;

namespace {


Scene instanced(PrimType type, std::uint64_t seed, double translate) {
  std::mt19937_64 rng(seed);
  Scene s;
  s.name = std::string("instanced ") + prim_type_key(type);
  s.geometries.push_back(make_random_geometry(type, 300, 0.004f, 0.05f, 1.0, seed));
  for (int i = 0; i < 3; ++i) s.instances.push_back({0, random_affine(rng, translate)});
  return s;
}

Mat3x4f mat(const float* p) {
  Mat3x4f m;
  std::memcpy(m.data(), p, sizeof(float) * 12);
  return m;
}

// Every leaf box of a cluster BLAS, as stored in fp32, contains its primitives' hulls
// under the map the kernel realises (stored world-to-local after the inverse stored
// frame), in double. Returns the number of (primitive, instance) pairs checked.
int check_cluster_boxes(const PackedScene& ps) {
  int checked = 0;
  for (const kernel::Instance& inst : ps.instances) {
    if (inst.prim != MASQ_INST_CLUSTER) continue;
    EXPECT_GE(inst.blas_root, 0);
    Affine3 realised = realised_object_to_local(mat(inst.world_to_object),
                                                mat(ps.frames.at(std::size_t(inst.scene_inst)).world_to_object));
    std::vector<int> stack{inst.blas_root};
    while (!stack.empty()) {
      const kernel::WideNode& n = ps.nodes.at(std::size_t(stack.back()));
      stack.pop_back();
      for (int i = 0; i < MASQ_WIDTH; ++i) {
        if (n.count[i] < 0) continue;
        if (n.count[i] == 0) {
          stack.push_back(n.child[i]);
          continue;
        }
        for (int j = 0; j < n.count[i]; ++j) {
          int prim = ps.refs.at(std::size_t(n.child[i] + j));
          Aabb b = hull_world_box(ball_hull(ps, inst.geom, prim), realised);
          EXPECT_LE(double(n.lo_x[i]), b.lo.x);
          EXPECT_LE(double(n.lo_y[i]), b.lo.y);
          EXPECT_LE(double(n.lo_z[i]), b.lo.z);
          EXPECT_GE(double(n.hi_x[i]), b.hi.x);
          EXPECT_GE(double(n.hi_y[i]), b.hi.y);
          EXPECT_GE(double(n.hi_z[i]), b.hi.z);
          ++checked;
        }
      }
    }
  }
  return checked;
}

class ClusterTypes : public ::testing::TestWithParam<PrimType> {};

TEST_P(ClusterTypes, ClustersPartitionThePrimitives) {
  Geometry g = make_random_geometry(GetParam(), 500, 0.004f, 0.05f, 1.0, 5);
  ClusterOptions opt;
  opt.max_size = 16; // not the default: the bound below is checked for a non-default size
  std::vector<std::int32_t> all(g.primitive_count());
  for (std::size_t i = 0; i < all.size(); ++i) all[i] = std::int32_t(i);
  std::vector<Cluster> cs = make_clusters(g, all, opt);
  std::multiset<std::int32_t> seen;
  for (const Cluster& c : cs) {
    EXPECT_GE(c.members.size(), 1u);
    EXPECT_LE(c.members.size(), 16u);
    seen.insert(c.members.begin(), c.members.end());
    // Orthonormal frame.
    glm::dmat3 id = glm::transpose(c.axes) * c.axes;
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) EXPECT_NEAR(id[a][b], a == b ? 1.0 : 0.0, 1e-12);
  }
  EXPECT_EQ(seen.size(), all.size());
  EXPECT_EQ(std::set<std::int32_t>(seen.begin(), seen.end()).size(), all.size());
  EXPECT_LT(cs.size(), all.size() / 4) << "clusters should be mostly full";
}

// Auto's cluster sizes share one class assignment: the clusters are the ones each size
// makes alone, and a cluster's member_area is its members' boxes in its frame, summed.
TEST_P(ClusterTypes, SharedClassAssignmentGivesEachSizesClusters) {
  Geometry g = make_random_geometry(GetParam(), 700, 0.004f, 0.05f, 1.0, 8);
  const std::vector<std::int32_t> all = every_primitive(g);
  ClusterOptions opt;
  const ClassAssignment assigned = assign_classes(g, all, opt.classes);
  for (int size : {8, 32, 256}) {
    opt.max_size = size;
    const std::vector<Cluster> alone = make_clusters(g, all, opt);
    const std::vector<Cluster> shared = make_clusters(g, all, opt, &assigned);
    ASSERT_EQ(alone.size(), shared.size()) << size;
    for (std::size_t i = 0; i < alone.size(); ++i) {
      EXPECT_EQ(alone[i].members, shared[i].members) << size;
      EXPECT_EQ(std::memcmp(&alone[i].axes, &shared[i].axes, sizeof(glm::dmat3)), 0) << size;
      EXPECT_EQ(alone[i].member_area, shared[i].member_area) << size;
      double sum = 0;
      for (std::int32_t p : alone[i].members) {
        const BallHull h = ball_hull(g, std::size_t(p));
        Aabb own;
        for (int k = 0; k < 3; ++k) {
          own.lo[k] = -h.support(-alone[i].axes[k]);
          own.hi[k] = h.support(alone[i].axes[k]);
        }
        sum += own.area();
      }
      EXPECT_EQ(alone[i].member_area, sum) << size;
    }
  }
  ClusterOptions other;
  other.classes = opt.classes / 2;
  EXPECT_THROW(make_clusters(g, all, other, &assigned), Error);
  const std::vector<std::int32_t> fewer(all.begin(), all.begin() + 100);
  EXPECT_THROW(make_clusters(g, fewer, opt, &assigned), Error);
}

// The member hulls make_clusters hands out (for the cluster BLAS and the mix's plan) are
// each cluster's ball_hull of every member, in member order, bit for bit; a plan given
// them plans as one that reads them itself, and hulls of other clusters are refused.
TEST_P(ClusterTypes, HandedOutHullsAreTheMembersHulls) {
  Geometry g = make_random_geometry(GetParam(), 500, 0.004f, 0.05f, 1.0, 9);
  const std::vector<std::int32_t> all = every_primitive(g);
  ClusterOptions opt;
  opt.max_size = 16;
  ClusterHulls hulls;
  const std::vector<Cluster> cs = make_clusters(g, all, opt, nullptr, &hulls);
  const std::vector<Cluster> plain = make_clusters(g, all, opt);
  ASSERT_EQ(cs.size(), plain.size());
  ASSERT_EQ(hulls.size(), cs.size());
  for (std::size_t i = 0; i < cs.size(); ++i) {
    EXPECT_EQ(cs[i].members, plain[i].members);
    ASSERT_EQ(hulls[i].size(), cs[i].members.size());
    for (std::size_t m = 0; m < hulls[i].size(); ++m) {
      const BallHull h = ball_hull(g, std::size_t(cs[i].members[m]));
      EXPECT_EQ(hulls[i][m].count, h.count);
      EXPECT_EQ(std::memcmp(hulls[i][m].centre.data(), h.centre.data(), sizeof h.centre), 0);
      EXPECT_EQ(std::memcmp(hulls[i][m].radius.data(), h.radius.data(), sizeof h.radius), 0);
    }
  }
  PlanOptions popt;
  popt.cluster = opt;
  const GeometryPlan read = plan_geometry(g, Method::Auto, popt, &cs);
  const GeometryPlan given = plan_geometry(g, Method::Auto, popt, &cs, &hulls);
  EXPECT_EQ(read.blas_prims, given.blas_prims);
  EXPECT_EQ(read.masq_prims, given.masq_prims);
  ASSERT_EQ(read.clusters.size(), given.clusters.size());
  EXPECT_TRUE(read.cluster_hulls.empty()); // nothing handed in, nothing handed on
  EXPECT_EQ(given.cluster_hulls.size(), given.clusters.size());
  ClusterHulls short_one = hulls;
  short_one.back().pop_back();
  EXPECT_THROW(plan_geometry(g, Method::Auto, popt, &cs, &short_one), Error);
  ClusterHulls fewer(hulls.begin(), hulls.end() - 1);
  EXPECT_THROW(plan_geometry(g, Method::Auto, popt, &cs, &fewer), Error);
}

TEST_P(ClusterTypes, AutoPlacesEveryPrimitiveOnce) {
  Geometry g = make_random_geometry(GetParam(), 400, 0.004f, 0.05f, 1.0, 6);
  PlanOptions opt;
  GeometryPlan plan = plan_geometry(g, Method::Auto, opt);
  std::multiset<std::int32_t> seen(plan.blas_prims.begin(), plan.blas_prims.end());
  seen.insert(plan.masq_prims.begin(), plan.masq_prims.end());
  for (const Cluster& c : plan.clusters) seen.insert(c.members.begin(), c.members.end());
  EXPECT_EQ(seen.size(), g.primitive_count());
  EXPECT_EQ(std::set<std::int32_t>(seen.begin(), seen.end()).size(), g.primitive_count());
}

TEST_P(ClusterTypes, LocalBoxesContainPrimitivesUnderStoredTransforms) {
  for (double translate : {1.5, 1e3, 1e5}) {
    Scene s = instanced(GetParam(), 7 + std::uint64_t(translate), translate);
    for (Method m : {Method::Cluster, Method::Auto}) {
      PackedScene ps = build_accel(s, m);
      int checked = check_cluster_boxes(ps);
      if (m == Method::Cluster) {
        EXPECT_EQ(checked, 300 * 3) << "every member of every instance";
      }
    }
  }
}

// Far from the origin the fp32 transform into a cluster's frame errs by much more than
// the box's rounding; the kernels' padding (and the rayquery backend's padded driver
// boxes) must keep every hit that ref finds, on every backend.
TEST_P(ClusterTypes, NoFalseCullsFarFromTheOrigin) {
  Scene s = instanced(GetParam(), 9, 1e4);
  glm::dvec3 centre = s.instances[0].object_to_world.translation;
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<kernel::Ray> rays;
  for (int i = 0; i < 20000; ++i) {
    glm::dvec3 to = centre + glm::dvec3(u(rng), u(rng), u(rng)) * 1.2;
    glm::dvec3 from = to + glm::normalize(glm::dvec3(u(rng), u(rng), u(rng))) * 30.0;
    rays.push_back(make_ray(from, to - from));
  }
  for (const std::string& name : backend_names()) {
    std::unique_ptr<Backend> be;
    try {
      be = make_backend(name);
    } catch (const BackendUnavailable& e) {
      ADD_FAILURE() << e.what();
      continue;
    }
    // The compute kernels give ref's BLAS and the cluster's members the same fp32 ray
    // (the world ray through the stored frame). The driver hands ref's intersector its
    // own object-space ray, which 1e4 from the origin differs by ~0.1 r, so on rayquery and
    // rtpipeline the cluster is compared with the cpu backend's cluster (the same ray as the shader's).
    std::vector<kernel::Hit> ref(rays.size()), clu(rays.size());
    if (driver_traversal(name)) {
      std::unique_ptr<Backend> cpu = make_backend("cpu");
      cpu->set_scene(build_accel(s, Method::Cluster));
      cpu->trace(rays, ref, {});
    } else {
      be->set_scene(build_accel(s, Method::Ref));
      be->trace(rays, ref, {});
    }
    // Full leaves (the default) and one member per leaf in clusters as large as auto
    // tries: other boxes, the same hits.
    for (double leaf_price : {4.0, 1.0}) {
      AccelOptions o;
      o.cluster.leaf_price = leaf_price;
      o.cluster.max_size = leaf_price == 1.0 ? kAutoLargeCluster : o.cluster.max_size;
      be->set_scene(build_accel(s, Method::Cluster, o));
      be->trace(rays, clu, {});
      int hits = 0, culled = 0, differ = 0;
      for (std::size_t i = 0; i < rays.size(); ++i) {
        hits += ref[i].prim >= 0;
        culled += ref[i].prim >= 0 && clu[i].prim < 0;
        // Across languages (C++ vs GLSL) the same formula may round differently (FMA).
        double tol = driver_traversal(name) ? 1e-4 * std::abs(double(ref[i].t)) : 0.0;
        differ += ref[i].prim != clu[i].prim || std::abs(double(ref[i].t) - double(clu[i].t)) > tol;
      }
      EXPECT_GT(hits, 200) << name;
      EXPECT_EQ(culled, 0) << name << ", leaf price " << leaf_price;
      EXPECT_EQ(differ, 0) << name << ", leaf price " << leaf_price << ": same intersector on the same ray";
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Types, ClusterTypes, ::testing::Values(PrimType::Capsule, PrimType::RoundCone, PrimType::Curve),
                         [](const ::testing::TestParamInfo<PrimType>& i) { return std::string(prim_type_key(i.param)); });

TEST(Clusters, SpheresAndTrianglesStayInTheBlas) {
  Scene s;
  s.geometries.push_back(make_random_geometry(PrimType::Sphere, 50, 0.01f, 0.05f, 1.0, 3));
  s.geometries.push_back(make_random_mesh(50, 1.0, 4));
  s.instances.push_back({0, Affine3{}});
  s.instances.push_back({1, Affine3{}});
  PackedScene ps = build_accel(s, Method::Cluster);
  EXPECT_EQ(ps.instances.size(), 2u);
  EXPECT_EQ(ps.stats.clusters, 0u);
}

TEST(Clusters, DefaultSceneFewerCallsThanRefWithinMemoryTarget) {
  Scene s = make_default_scene();
  std::vector<kernel::Ray> rays = make_camera_rays(s.camera, 128, 96);
  std::unique_ptr<Backend> cpu = make_backend("cpu");
  double calls[4] = {0, 0, 0, 0};
  std::size_t bytes[4] = {0, 0, 0, 0};
  for (Method m : {Method::Ref, Method::Masq, Method::Cluster, Method::Auto}) {
    PackedScene ps = build_accel(s, m);
    bytes[int(m)] = ps.acceleration_bytes();
    cpu->set_scene(ps);
    std::vector<kernel::Hit> hits(rays.size());
    std::vector<kernel::RayStats> stats(rays.size());
    cpu->trace(rays, hits, stats);
    for (const kernel::RayStats& st : stats) calls[int(m)] += st.isect_calls;
  }
  for (int m = 0; m < 4; ++m)
    std::printf("%-7s isect/ray %.3f, accel bytes/prim %.1f\n", method_name(Method(m)), calls[m] / rays.size(),
                double(bytes[m]) / double(s.primitive_count()));
  EXPECT_LE(calls[int(Method::Cluster)], 0.7 * calls[int(Method::Ref)]);
  EXPECT_LE(double(bytes[int(Method::Cluster)]), 1.2 * double(bytes[int(Method::Ref)]));
}

} // namespace
