// Every backend x every method against the independent long-double oracle, on the
// default scene and on randomised scenes with instancing (rotation, non-uniform scale,
// translation) and non-unit ray directions.
//
// Tolerances, and why:
//  - kClearance = 1e-3: rays passing within 0.1% of a radius of a capsule's surface, or
//    within barycentric 1e-3 of a triangle edge, are ambiguous in fp32 (the ray itself
//    is rounded input; its distance to the axis carries ~1e-7 relative error of the
//    distance travelled). They are counted, not compared.
//  - kSeparation = 1e-4: where the oracle's two nearest hits on different primitives are
//    closer than this (relative), either primitive is an acceptable answer.
//  - kRelT = 1e-4: t within 1e-4 relative (fp32 leaves ~1e-6 here; grazing hits amplify).
//  - Normals within 1e-2 (cosine > 0.99995 ~ 0.6 degrees) where the hit is unambiguous;
//    curves within 3e-2 (1.7 degrees): the phantom intersector accepts a crossing once
//    its residual is below 2^-7 r, which tilts the normal by up to ~0.45 degrees before
//    a non-uniformly scaled instance transform stretches it.
#include "bvh/twolevel/build_accel.h"
#include "host/backend.h"
#include "oracle/oracle.h"
#include "scenes/camera.h"
#include "scenes/curve_tools.h"
#include "scenes/generators.h"
#include "tests/random_rays.h"
#include <gtest/gtest.h>
#include <cmath>
#include <random>
#include "tests/random_affine.h"
#include "tests/test_env.h"

using namespace masq;
using masq::test::random_rays;
using masq::test::random_affine;

namespace {

constexpr long double kClearance = 1e-3;
constexpr long double kSeparation = 1e-4;
constexpr double kRelT = 1e-4;
constexpr double kNormal = 1e-2;
constexpr double kCurveNormal = 3e-2;

struct Tally {
  int compared = 0, ambiguous = 0, hits = 0;
  int wrong_hit_miss = 0, wrong_prim = 0, wrong_t = 0, wrong_normal = 0;
  std::string first_failure;
};

Tally compare(const Scene& scene, const std::vector<kernel::Ray>& rays, const std::vector<oracle::OracleHit>& truth,
              const std::vector<kernel::Hit>& hits) {
  Tally t;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    const oracle::OracleHit& o = truth[i];
    const kernel::Hit& h = hits[i];
    if (o.clearance < kClearance) {
      ++t.ambiguous;
      continue;
    }
    ++t.compared;
    auto fail = [&](int& counter, const std::string& what) {
      ++counter;
      if (t.first_failure.empty())
        t.first_failure = "ray " + std::to_string(i) + ": " + what + " (oracle prim " + std::to_string(o.prim) +
                          " geom " + std::to_string(o.geom) + " inst " + std::to_string(o.inst) + " t " +
                          std::to_string(double(o.t)) + "; got prim " + std::to_string(h.prim) + " geom " +
                          std::to_string(h.geom) + " inst " + std::to_string(h.inst) + " t " + std::to_string(h.t) + ")";
    };
    if ((o.prim >= 0) != (h.prim >= 0)) {
      fail(t.wrong_hit_miss, "hit/miss differs");
      continue;
    }
    if (o.prim < 0) continue;
    ++t.hits;
    bool separated = (o.second_t - o.t) > kSeparation * o.t;
    if (separated && (o.prim != h.prim || o.geom != h.geom || o.inst != h.inst)) {
      fail(t.wrong_prim, "different primitive");
      continue;
    }
    if (std::abs(double(o.t) - h.t) > kRelT * double(o.t)) fail(t.wrong_t, "t differs");
    if (separated) {
      double c = o.normal.x * h.normal[0] + o.normal.y * h.normal[1] + o.normal.z * h.normal[2];
      double tol = scene.geometries[std::size_t(o.geom)].type == PrimType::Curve ? kCurveNormal : kNormal;
      if (1.0 - c > tol * tol / 2) fail(t.wrong_normal, "normal differs");
    }
  }
  return t;
}

std::unique_ptr<Backend> backend_or_fail(const std::string& name) {
  return masq::test::open_or_fail(name, [](const std::string& n) { return make_backend(n); });
}

void check_all_backends(const Scene& scene, const std::vector<kernel::Ray>& rays, const AccelOptions& opt = {}) {
  oracle::Oracle oracle(scene, {.exact_clearance_below = 1}); // clearance read below kClearance only
  std::vector<oracle::OracleHit> truth = oracle.trace_all(rays);
  for (const std::string& name : masq::test::tested_backends(backend_names())) {
    std::unique_ptr<Backend> be = backend_or_fail(name);
    if (!be) continue;
    // Method auto twice: as it decides (one candidate's structure), and its per-cluster
    // mix alone, whose TLAS holds BLAS, masquerade and cluster instances together.
    for (int k = 0; k < 5; ++k) {
      Method m = k < 4 ? Method(k) : Method::Auto;
      AccelOptions o = opt;
      if (k == 4) o.auto_select = AutoSelect::MixOnly;
      std::string label = k == 4 ? "auto-mix" : method_name(m);
      SCOPED_TRACE(name + " " + label + " " + mode_name(opt.mode) + " on " + scene.name);
      be->set_scene(build_accel(scene, m, o));
      std::vector<kernel::Hit> hits(rays.size());
      be->trace(rays, hits, {});
      Tally t = compare(scene, rays, truth, hits);
      EXPECT_GT(t.hits, 0);
      EXPECT_LT(t.ambiguous, int(rays.size() / 8)) << "too few rays compared";
      if (opt.mode == Mode::Robust) {
        EXPECT_EQ(t.wrong_hit_miss, 0) << t.first_failure;
        EXPECT_EQ(t.wrong_prim, 0) << t.first_failure;
        EXPECT_EQ(t.wrong_t, 0) << t.first_failure;
        EXPECT_EQ(t.wrong_normal, 0) << t.first_failure;
      } else {
        // The fast intersectors lose digits by design (measured by `masq stress`); here
        // they must still find the right primitive on all but a few rays.
        EXPECT_LE(t.wrong_hit_miss + t.wrong_prim, t.compared / 50) << t.first_failure;
        std::printf("  fast mode: %d hit/miss, %d primitive, %d t, %d normal differences\n", t.wrong_hit_miss,
                    t.wrong_prim, t.wrong_t, t.wrong_normal);
      }
      std::printf("[ %-8s %-8s %-6s ] %s: %d rays compared, %d hits, %d ambiguous skipped\n", name.c_str(),
                  label.c_str(), mode_name(opt.mode), scene.name.c_str(), t.compared, t.hits, t.ambiguous);
    }
  }
}


} // namespace

TEST(CrossBackend, DefaultSceneOrthographicLikeThePaper) {
  // The paper's view: orthographic rays along +z through the tilted bundle.
  Scene s = make_default_scene();
  s.camera.eye = {0.0, 0.0, -5.0};
  s.camera.target = {0.0, 0.0, 0.0};
  s.camera.orthographic = true;
  s.camera.ortho_height = 1.8;
  check_all_backends(s, make_camera_rays(s.camera, 160, 160));
}

TEST(CrossBackend, DefaultSceneCamera) {
  Scene s = make_default_scene();
  check_all_backends(s, make_camera_rays(s.camera, 96, 72));
}

TEST(CrossBackend, RandomInstancedScenes) {
  for (std::uint64_t seed : {11u, 12u}) {
    std::mt19937_64 rng(seed);
    Scene s;
    s.name = "random" + std::to_string(seed);
    s.geometries.push_back(make_random_capsules(300, 0.004f, 0.05f, 1.0, seed));
    s.geometries.push_back(make_random_mesh(200, 1.0, seed + 100));
    for (int i = 0; i < 3; ++i) s.instances.push_back({0, random_affine(rng)});
    for (int i = 0; i < 2; ++i) s.instances.push_back({1, random_affine(rng)});
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    std::vector<kernel::Ray> rays;
    for (int i = 0; i < 4096; ++i) {
      glm::dvec3 from = glm::normalize(glm::dvec3(u(rng), u(rng), u(rng))) * 5.0;
      glm::dvec3 to = glm::dvec3(u(rng), u(rng), u(rng)) * 1.5;
      double scale = 0.3 + 2.0 * std::abs(u(rng)); // non-unit directions
      rays.push_back(make_ray(from, (to - from) * (scale / glm::length(to - from))));
    }
    check_all_backends(s, rays);
  }
}


class EveryPrimitive : public ::testing::TestWithParam<PrimType> {};

TEST_P(EveryPrimitive, InstancedWithMeshRobustAndFast) {
  // Each thin primitive type, instanced (rotation, non-uniform scale, translation)
  // beside a triangle mesh, in both modes.
  PrimType type = GetParam();
  std::mt19937_64 rng(21 + int(type));
  Scene s;
  s.name = std::string("random ") + prim_type_key(type);
  s.geometries.push_back(make_random_geometry(type, 200, 0.004f, 0.05f, 1.0, 31 + int(type)));
  s.geometries.push_back(make_random_mesh(128, 1.0, 41));
  for (int i = 0; i < 3; ++i) s.instances.push_back({0, random_affine(rng)});
  s.instances.push_back({1, random_affine(rng)});
  std::vector<kernel::Ray> rays = random_rays(rng, 3072);
  for (Mode mode : {Mode::Robust, Mode::Fast}) {
    AccelOptions opt;
    opt.mode = mode;
    check_all_backends(s, rays, opt);
  }
}

// Oriented wide nodes (node format o4) with every BLAS node rotated, the format's
// numerical worst case (each node test rotates the ray and pads by the rotation's fp32
// error): every backend and method against the oracle, robust mode, no false cull.
TEST_P(EveryPrimitive, EveryNodeRotated) {
  PrimType type = GetParam();
  std::mt19937_64 rng(61 + int(type));
  Scene s;
  s.name = std::string("random ") + prim_type_key(type) + ", o4 every node rotated";
  s.geometries.push_back(make_random_geometry(type, 200, 0.004f, 0.05f, 1.0, 71 + int(type)));
  s.geometries.push_back(make_random_mesh(128, 1.0, 43));
  for (int i = 0; i < 2; ++i) s.instances.push_back({0, random_affine(rng)});
  s.instances.push_back({1, random_affine(rng)});
  AccelOptions opt;
  opt.nodes = NodeFormat::O4;
  opt.oriented_gain = INFINITY;
  PackedScene ps = build_accel(s, Method::Ref, opt);
  ASSERT_EQ(ps.stats.oriented_nodes, ps.stats.blas_nodes) << "every BLAS node is rotated";
  check_all_backends(s, random_rays(rng, 3072), opt);
}

// The o4 format as users build it (nodes rotated where the SAH gains) on the default scene.
TEST(CrossBackend, DefaultSceneCameraOrientedNodes) {
  Scene s = make_default_scene();
  AccelOptions opt;
  opt.nodes = NodeFormat::O4;
  EXPECT_GT(build_accel(s, Method::Ref, opt).stats.oriented_nodes, 0u);
  check_all_backends(s, make_camera_rays(s.camera, 96, 72), opt);
}

TEST_P(EveryPrimitive, BundleCamera) {
  BundleParams p;
  p.count = 300;
  p.radius = 0.004f;
  p.prim = GetParam();
  Scene s = make_default_scene(p);
  s.name = std::string("bundle of ") + prim_type_key(p.prim);
  check_all_backends(s, make_camera_rays(s.camera, 96, 72));
}

INSTANTIATE_TEST_SUITE_P(Types, EveryPrimitive,
                         ::testing::Values(PrimType::Capsule, PrimType::RoundCone, PrimType::Sphere, PrimType::Curve,
                                           PrimType::Ribbon),
                         [](const ::testing::TestParamInfo<PrimType>& i) { return std::string(prim_type_key(i.param)); });

TEST(CrossBackend, SubdividedCurvesWithPaperObbs) {
  BundleParams p;
  p.count = 200;
  p.radius = 0.004f;
  p.prim = PrimType::Curve;
  Scene s = subdivide_curves(make_default_scene(p), 4);
  AccelOptions opt;
  opt.curve_obb = CurveObb::Paper;
  check_all_backends(s, make_camera_rays(s.camera, 96, 72), opt);
}

TEST(CrossBackend, MasqueradeHalvesIntersectorCallsOnDefaultScene) {
  Scene s = make_default_scene();
  std::vector<kernel::Ray> rays = make_camera_rays(s.camera, 128, 96);
  std::unique_ptr<Backend> cpu = make_backend("cpu");
  double calls[2] = {0, 0};
  for (Method m : {Method::Ref, Method::Masq}) {
    cpu->set_scene(build_accel(s, m));
    std::vector<kernel::Hit> hits(rays.size());
    std::vector<kernel::RayStats> stats(rays.size());
    cpu->trace(rays, hits, stats);
    for (const kernel::RayStats& st : stats) calls[int(m)] += st.isect_calls;
  }
  std::printf("intersector calls per ray: ref %.3f masq %.3f (ratio %.2f)\n", calls[0] / rays.size(),
              calls[1] / rays.size(), calls[0] / calls[1]);
  EXPECT_LE(calls[1], 0.5 * calls[0]);
}

TEST(CrossBackend, InvalidRaysMissOnEveryBackend) {
  Scene s = make_default_scene();
  std::vector<kernel::Ray> rays = make_camera_rays(s.camera, 4, 4);
  rays[0].org[0] = NAN;
  rays[1].dir[1] = INFINITY;
  rays[2].dir[0] = rays[2].dir[1] = rays[2].dir[2] = 0.0f;
  rays[3].tmin = 10.0f;
  rays[3].tmax = 1.0f;
  for (const std::string& name : masq::test::tested_backends(backend_names())) {
    std::unique_ptr<Backend> be = backend_or_fail(name);
    if (!be) continue;
    be->set_scene(build_accel(s, Method::Masq));
    std::vector<kernel::Hit> hits(rays.size());
    be->trace(rays, hits, {});
    for (int i = 0; i < 4; ++i) EXPECT_LT(hits[i].prim, 0) << name << " ray " << i;
  }
}

// One BLAS under one identity instance (a bare bundle, no ground): ref runs the variant
// without a TLAS stage (KernelFeatures::single_blas) and must still agree with the
// oracle on every backend; on cpu its counters show no TLAS visit and no transform.
TEST(CrossBackend, SingleIdentityInstanceSkipsTheTlas) {
  BundleParams p;
  p.count = 300;
  p.radius = 0.004f;
  Scene s = make_default_scene(p);
  s.geometries.resize(1); // the bundle only: drop the ground plane and its instance
  s.instances = {{0, {}}};
  s.name = "bare bundle (one identity instance)";
  ASSERT_TRUE(build_accel(s, Method::Ref).features.single_blas);
  ASSERT_FALSE(build_accel(s, Method::Masq).features.single_blas);
  std::vector<kernel::Ray> rays = make_camera_rays(s.camera, 96, 72);
  check_all_backends(s, rays);
  std::unique_ptr<Backend> cpu = make_backend("cpu");
  cpu->set_scene(build_accel(s, Method::Ref));
  std::vector<kernel::Hit> hits(rays.size());
  std::vector<kernel::RayStats> stats(rays.size());
  cpu->trace(rays, hits, stats);
  long tlas = 0, transforms = 0, blas = 0;
  for (const kernel::RayStats& r : stats) tlas += r.tlas_nodes, transforms += r.transforms, blas += r.blas_nodes;
  EXPECT_EQ(tlas, 0);
  EXPECT_EQ(transforms, 0);
  EXPECT_GT(blas, 0);
}

// Every backend walks the same nodes in the same order: children by entry distance, ties
// in slot order (kernels/child_order.h: an insertion sort on cpu and OpenCL, a sorting
// network on Vulkan), the nearest inner child held for the next visit (kernels/traverse.h).
// So the compute backends' per-ray counters must equal the cpu's, ray by ray, for
// closest-hit and occlusion queries (the latter in both BLAS occlusion orders), every
// node format and the methods with a TLAS, masquerade instances and clusters.
TEST(CrossBackend, ComputeBackendsVisitWhatTheCpuVisits) {
  Scene s = make_default_scene();
  std::vector<kernel::Ray> rays = make_camera_rays(s.camera, 48, 36);
  std::vector<kernel::Ray> extra = random_rays(99, 1500);
  rays.insert(rays.end(), extra.begin(), extra.end());
  std::unique_ptr<Backend> cpu = make_backend("cpu");
  int compared = 0;
  for (NodeFormat f : node_format_table.values())
    for (Method m : {Method::Ref, Method::Masq, Method::Cluster})
      for (BlasOcclusion order : blas_occlusion_table.values()) {
        AccelOptions o;
        o.nodes = f;
        o.blas_occlusion = order;
        const PackedScene ps = build_accel(s, m, o);
        for (Query q : {Query::Closest, Query::Any}) {
          if (q == Query::Closest && order != BlasOcclusion::Nearest) continue; // the order is occlusion's alone
          std::vector<kernel::Hit> want_hits(rays.size());
          std::vector<kernel::RayStats> want(rays.size());
          cpu->set_scene(ps);
          cpu->trace(rays, want_hits, want, q);
          for (const std::string& name : {std::string("vulkan"), std::string("opencl")}) {
            std::unique_ptr<Backend> be = backend_or_fail(name);
            if (!be) continue;
            SCOPED_TRACE(name + " " + method_name(m) + " " + node_format_name(f) +
                         (q == Query::Any ? std::string(" occlusion, BLAS ") + blas_occlusion_name(order) : " closest"));
            be->set_scene(ps);
            std::vector<kernel::Hit> hits(rays.size());
            std::vector<kernel::RayStats> got(rays.size());
            be->trace(rays, hits, got, q);
            int differ = 0;
            for (std::size_t i = 0; i < rays.size(); ++i) {
              const kernel::RayStats& a = got[i];
              const kernel::RayStats& b = want[i];
              if (a.tlas_nodes == b.tlas_nodes && a.blas_nodes == b.blas_nodes && a.transforms == b.transforms &&
                  a.isect_calls == b.isect_calls)
                continue;
              if (differ++ < 3)
                ADD_FAILURE() << "ray " << i << ": tlas/blas/transforms/isect " << a.tlas_nodes << "/" << a.blas_nodes
                              << "/" << a.transforms << "/" << a.isect_calls << ", cpu " << b.tlas_nodes << "/"
                              << b.blas_nodes << "/" << b.transforms << "/" << b.isect_calls;
            }
            EXPECT_EQ(differ, 0) << "rays whose counters differ from the cpu's";
            ++compared;
          }
        }
      }
  if (compared == 0) GTEST_SKIP() << "no compute backend besides the cpu (MASQ_ALLOW_MISSING_BACKENDS=1)";
}
