// The occlusion (any-hit, early exit) kernel variant on every backend: a shadow ray is
// occluded exactly when the long-double oracle finds a hit in [tmin, tmax], the closest-hit
// query hits it too, the hit it reports lies in the ray's window, and it does no more
// work than the closest-hit variant. On the default scene (capsules over a ground plane)
// and on hair of chained cubic curves with both curve intersectors, whose occlusion
// calls stop at the first certificate of a crossing (kernels/curve_occlusion.h): a point
// inside the strand that a shadow ray starting on its far side goes back through, or an
// entry not necessarily the nearest.
#include "bench/ray_sets.h"
#include "bvh/twolevel/build_accel.h"
#include "host/backend.h"
#include "oracle/oracle.h"
#include "scenes/camera.h"
#include "scenes/generators.h"
#include "scenes/strand_generators.h"
#include <cmath>
#include <ostream>
#include <gtest/gtest.h>
#include "tests/test_env.h"

using namespace masq;

namespace {

std::unique_ptr<Backend> backend_or_fail(const std::string& name) {
  return masq::test::open_or_fail(name, [](const std::string& n) { return make_backend(n); });
}

double mean_calls(const std::vector<kernel::RayStats>& s) {
  double c = 0;
  for (const kernel::RayStats& r : s) c += r.isect_calls;
  return c / double(s.size());
}

// The scenes: the default one, or strands of chained cubic curves traced with one of the
// two curve intersectors.
enum class SceneKind { Default, HairPhantom, HairRoving };

struct Case {
  std::string backend;
  Method method;
  SceneKind scene = SceneKind::Default;
};
const char* scene_name(SceneKind k) {
  return k == SceneKind::Default ? "default" : (k == SceneKind::HairPhantom ? "curves_phantom" : "curves_roving");
}
void PrintTo(const Case& c, std::ostream* os) { *os << c.backend << " " << method_name(c.method) << " " << scene_name(c.scene); }

// A curtain of wavy strands in three layers, as chained Catmull-Rom pieces meeting at
// shared end balls (as real hair files give them), dense enough that most camera rays hit
// and that shadow rays cross other strands, small enough for the brute-force oracle
// (123 strands of 12 points: 1,353 pieces).
Scene curtain_of_curves() {
  std::vector<Strand> strands;
  for (int layer = 0; layer < 3; ++layer)
    for (int k = 0; k <= 40; ++k) {
      Strand st;
      for (int j = 0; j < 12; ++j) {
        const double y = -0.5 + j / 11.0, x = -0.4 + 0.02 * k + 0.01 * layer;
        st.points.push_back({x + 0.03 * std::sin(7.0 * y + k), y, 0.03 * layer + 0.01 * std::cos(5.0 * y + 2 * k)});
        st.radii.push_back(0.012);
      }
      strands.push_back(st);
    }
  Scene s;
  s.name = "curtain";
  s.geometries.push_back(strands_to_geometry(strands, PrimType::Curve));
  s.instances.push_back({0, {}});
  s.camera.eye = {0.3, 0.2, -2.0};
  return s;
}

// Shadow rays from the scene's primary hits (96 x 96 camera rays, traced on the cpu).
std::vector<kernel::Ray> shadow_rays(const Scene& scene, const AccelOptions& opt) {
  std::unique_ptr<Backend> cpu = make_backend("cpu");
  cpu->set_scene(build_accel(scene, Method::Ref, opt));
  std::vector<kernel::Ray> primary = make_camera_rays(scene.camera, 96, 96);
  std::vector<kernel::Hit> primary_hits(primary.size());
  cpu->trace(primary, primary_hits, {});
  return make_secondary_rays(RaySet::Shadow, scene, primary, primary_hits);
}

class Occlusion : public ::testing::TestWithParam<Case> {};

TEST_P(Occlusion, AgreesWithTheOracleAndStopsEarly) {
  const Case& c = GetParam();
  std::unique_ptr<Backend> be = backend_or_fail(c.backend);
  if (!be) GTEST_SKIP() << c.backend << " unavailable";
  Scene scene = c.scene == SceneKind::Default ? make_default_scene() : curtain_of_curves();
  AccelOptions opt;
  opt.curve_isect = c.scene == SceneKind::HairPhantom ? CurveIsect::Phantom : CurveIsect::Roving;
  std::vector<kernel::Ray> rays = shadow_rays(scene, opt);
  ASSERT_GT(rays.size(), 1000u);

  be->set_scene(build_accel(scene, c.method, opt));
  std::vector<kernel::Hit> any(rays.size()), closest(rays.size());
  std::vector<kernel::RayStats> any_stats(rays.size()), closest_stats(rays.size());
  be->trace(rays, any, any_stats, Query::Any);
  be->trace(rays, closest, closest_stats, Query::Closest);

  oracle::Oracle oracle(scene, {.exact_clearance_below = 1}); // clearance read below 1e-4 only
  std::vector<oracle::OracleHit> truth = oracle.trace_all(rays);
  int occluded = 0, wrong = 0, not_a_hit = 0, closest_differs = 0, inside_witness = 0;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    const bool a = any[i].prim >= 0;
    occluded += a;
    closest_differs += a != (closest[i].prim >= 0);
    // An interior point of the primitive the closest hit leaves (curve_occlusion.h).
    inside_witness += a && any[i].prim == closest[i].prim && any[i].t < closest[i].t;
    // Rays whose answer fp32 may legitimately flip (the oracle's clearance band, as in
    // the cross-backend test) are not counted against the kernel.
    const bool ambiguous = truth[i].clearance < 1e-4L;
    if (a != (truth[i].prim >= 0) && !ambiguous) ++wrong;
    if (a && !(any[i].t >= rays[i].tmin && any[i].t <= rays[i].tmax)) ++not_a_hit;
  }
  EXPECT_EQ(closest_differs, 0) << "occluded must mean the closest-hit query hits";
  EXPECT_LE(wrong, int(rays.size() / 10000)) << occluded << " occluded of " << rays.size();
  EXPECT_EQ(not_a_hit, 0);
  EXPECT_GT(occluded, int(rays.size() / 10)); // the bundle shadows much of the ground, strands each other
  // Curves: rays from a strand's far side prove their occlusion by a point inside it.
  if (c.scene != SceneKind::Default) {
    EXPECT_GT(inside_witness, 0);
  }
  // Early exit: fewer intersector calls than the closest-hit query on the same rays.
  EXPECT_LT(mean_calls(any_stats), mean_calls(closest_stats));
}

// The BLAS occlusion order (AccelOptions::blas_occlusion) changes only how soon a shadow
// ray meets an occluder: starts-last must occlude exactly the rays nearest-first does, on
// every backend, and must be the walk taken (some rays' counters differ) wherever the walk
// is masq's kernel's (cpu, vulkan, opencl; not the driver's). On the default
// scene and the curtain of curves, the methods whose BLAS have inner nodes.
TEST(OcclusionOrder, StartsLastOccludesTheRaysNearestFirstDoes) {
  for (SceneKind k : {SceneKind::Default, SceneKind::HairRoving}) {
    Scene scene = k == SceneKind::Default ? make_default_scene() : curtain_of_curves();
    AccelOptions opt;
    opt.curve_isect = CurveIsect::Roving;
    std::vector<kernel::Ray> rays = shadow_rays(scene, opt);
    ASSERT_GT(rays.size(), 1000u);
    for (Method m : {Method::Ref, Method::Cluster}) {
      opt.blas_occlusion = BlasOcclusion::Nearest;
      const PackedScene nearest = build_accel(scene, m, opt);
      opt.blas_occlusion = BlasOcclusion::StartsLast;
      const PackedScene starts_last = build_accel(scene, m, opt);
      EXPECT_FALSE(nearest.features.blas_starts_last);
      EXPECT_TRUE(starts_last.features.blas_starts_last);
      for (const std::string& name : backend_names()) {
        std::unique_ptr<Backend> be = backend_or_fail(name);
        if (!be) continue;
        SCOPED_TRACE(name + " " + method_name(m) + " " + scene_name(k));
        std::vector<kernel::Hit> a(rays.size()), b(rays.size());
        std::vector<kernel::RayStats> sa(rays.size()), sb(rays.size());
        be->set_scene(nearest);
        be->trace(rays, a, sa, Query::Any);
        be->set_scene(starts_last);
        be->trace(rays, b, sb, Query::Any);
        int flipped = 0, walked_otherwise = 0, occluded = 0;
        for (std::size_t i = 0; i < rays.size(); ++i) {
          occluded += a[i].prim >= 0;
          flipped += (a[i].prim >= 0) != (b[i].prim >= 0);
          walked_otherwise += sa[i].blas_nodes != sb[i].blas_nodes || sa[i].isect_calls != sb[i].isect_calls;
        }
        EXPECT_EQ(flipped, 0) << "rays occluded in one order and not the other, of " << occluded << " occluded";
        // rayquery and rtpipeline: the driver walks, in its own order.
        if (name == "cpu" || name == "vulkan" || name == "opencl") {
          EXPECT_GT(walked_otherwise, 0) << "starts-last walked every ray as nearest-first does";
        }
      }
    }
  }
}

std::vector<Case> cases() {
  std::vector<Case> out;
  for (const std::string& b : backend_names()) {
    for (Method m : {Method::Ref, Method::Masq, Method::Cluster, Method::Auto}) out.push_back({b, m});
    for (SceneKind k : {SceneKind::HairPhantom, SceneKind::HairRoving})
      for (Method m : {Method::Ref, Method::Masq}) out.push_back({b, m, k});
  }
  return out;
}

INSTANTIATE_TEST_SUITE_P(EveryBackend, Occlusion, ::testing::ValuesIn(cases()),
                         [](const ::testing::TestParamInfo<Case>& p) {
                           const Case& c = p.param;
                           return c.backend + "_" + method_name(c.method) +
                                  (c.scene == SceneKind::Default ? "" : std::string("_") + scene_name(c.scene));
                         });

} // namespace
