// The occlusion (any-hit, early exit) kernel variant on every backend: a shadow ray is
// occluded exactly when the long-double oracle finds a hit in [tmin, tmax], the hit it
// reports is a real one (the oracle hits that primitive), and it does no more work than
// the closest-hit variant.
#include "bench/ray_sets.h"
#include "bvh/twolevel/build_accel.h"
#include "host/backend.h"
#include "oracle/oracle.h"
#include "scenes/camera.h"
#include "scenes/generators.h"
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

struct Case {
  std::string backend;
  Method method;
};
void PrintTo(const Case& c, std::ostream* os) { *os << c.backend << " " << method_name(c.method); }

class Occlusion : public ::testing::TestWithParam<Case> {};

TEST_P(Occlusion, AgreesWithTheOracleAndStopsEarly) {
  const Case& c = GetParam();
  std::unique_ptr<Backend> be = backend_or_fail(c.backend);
  if (!be) GTEST_SKIP() << c.backend << " unavailable";
  // The default scene (bundle over a ground plane): shadow rays from its primary hits.
  Scene scene = make_default_scene();
  std::unique_ptr<Backend> cpu = make_backend("cpu");
  PackedScene ref = build_accel(scene, Method::Ref);
  cpu->set_scene(ref);
  std::vector<kernel::Ray> primary = make_camera_rays(scene.camera, 96, 96);
  std::vector<kernel::Hit> primary_hits(primary.size());
  cpu->trace(primary, primary_hits, {});
  std::vector<kernel::Ray> rays = make_secondary_rays(RaySet::Shadow, scene, primary, primary_hits);
  ASSERT_GT(rays.size(), 1000u);

  be->set_scene(build_accel(scene, c.method));
  std::vector<kernel::Hit> any(rays.size()), closest(rays.size());
  std::vector<kernel::RayStats> any_stats(rays.size()), closest_stats(rays.size());
  be->trace(rays, any, any_stats, Query::Any);
  be->trace(rays, closest, closest_stats, Query::Closest);

  oracle::Oracle oracle(scene, {.exact_clearance_below = 1}); // clearance read below 1e-4 only
  std::vector<oracle::OracleHit> truth = oracle.trace_all(rays);
  int occluded = 0, wrong = 0, not_a_hit = 0, closest_differs = 0;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    const bool a = any[i].prim >= 0;
    occluded += a;
    closest_differs += a != (closest[i].prim >= 0);
    // Rays whose answer fp32 may legitimately flip (the oracle's clearance band, as in
    // the cross-backend test) are not counted against the kernel.
    const bool ambiguous = truth[i].clearance < 1e-4L;
    if (a != (truth[i].prim >= 0) && !ambiguous) ++wrong;
    if (a && !(any[i].t >= rays[i].tmin && any[i].t <= rays[i].tmax)) ++not_a_hit;
  }
  EXPECT_EQ(closest_differs, 0) << "occluded must mean the closest-hit query hits";
  EXPECT_LE(wrong, int(rays.size() / 10000)) << occluded << " occluded of " << rays.size();
  EXPECT_EQ(not_a_hit, 0);
  EXPECT_GT(occluded, int(rays.size() / 10)); // the bundle shadows much of the ground
  // Early exit: fewer intersector calls than the closest-hit query on the same rays.
  EXPECT_LT(mean_calls(any_stats), mean_calls(closest_stats));
}

std::vector<Case> cases() {
  std::vector<Case> out;
  for (const std::string& b : backend_names())
    for (Method m : {Method::Ref, Method::Masq, Method::Cluster, Method::Auto}) out.push_back({b, m});
  return out;
}

INSTANTIATE_TEST_SUITE_P(EveryBackend, Occlusion, ::testing::ValuesIn(cases()),
                         [](const ::testing::TestParamInfo<Case>& p) { return p.param.backend + "_" + method_name(p.param.method);
});

} // namespace
