// Limits that split work on the device without changing any result:
//  - MASQ_MAX_RAYS_PER_DISPATCH (host/limit_knob.h): a trace in dispatches of at most
//    that many rays gives bit-for-bit the hits and counters of one dispatch, on every
//    backend and bv tracer that dispatches (the cpu traces in place and has no cap);
//  - MASQ_VK_MAX_ALLOCATIONS: ray query builds a cluster scene's thousands of BLAS in
//    batches sub-allocated from a few buffers (host/vulkan/accel_batch.cpp), so 64 live
//    allocations hold it, with the same hits and counters; a limit too low to hold the
//    scene is one clear error;
//  - the trace timing's parts (host/backend.h TraceTiming) lie within its wall time.
#include "bvh/bv/bv_scene.h"
#include "bvh/twolevel/build_accel.h"
#include "host/backend.h"
#include "host/bv_tracer.h"
#include "host/vulkan/rayquery_plan.h"
#include "scenes/camera.h"
#include "scenes/generators.h"
#include <gtest/gtest.h>
#include <cstdlib>
#include <cstring>
#include <random>
#include <string>
#include "tests/test_env.h"

using namespace masq;
using kernel::Hit;
using kernel::Ray;
using kernel::RayStats;

namespace {

using masq::test::ScopedEnv;

Scene capsule_scene(int count, std::uint64_t seed) {
  Scene s;
  s.name = "random capsules";
  s.geometries.push_back(make_random_geometry(PrimType::Capsule, count, 0.002f, 0.02f, 1.0, seed));
  s.instances.push_back({0, glm::dmat4(1.0)});
  return s;
}

// n rays from a sphere of radius 5 towards the unit cube (a prime count: the last
// dispatch is partial).
std::vector<Ray> random_rays(std::uint64_t seed, int n) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<Ray> rays;
  for (int i = 0; i < n; ++i) {
    glm::dvec3 from = glm::normalize(glm::dvec3(u(rng), u(rng), u(rng))) * 5.0;
    glm::dvec3 to = glm::dvec3(u(rng), u(rng), u(rng));
    rays.push_back(make_ray(from, to - from));
  }
  return rays;
}

struct Result {
  std::vector<Hit> hits;
  std::vector<RayStats> stats;
};

template <class Tracer, class... Q>
Result trace(Tracer& t, const std::vector<Ray>& rays, Q... query) {
  Result r{std::vector<Hit>(rays.size()), std::vector<RayStats>(rays.size())};
  t.trace(rays, r.hits, r.stats, query...);
  return r;
}

// Bit-for-bit, with the first differing ray named.
void expect_same(const Result& want, const Result& got) {
  ASSERT_EQ(want.hits.size(), got.hits.size());
  int hits = 0;
  for (std::size_t i = 0; i < want.hits.size(); ++i) {
    hits += want.hits[i].prim >= 0;
    ASSERT_EQ(std::memcmp(&want.hits[i], &got.hits[i], sizeof(Hit)), 0) << "hit of ray " << i;
    ASSERT_EQ(std::memcmp(&want.stats[i], &got.stats[i], sizeof(RayStats)), 0) << "counters of ray " << i;
  }
  EXPECT_GT(hits, 100); // the rays see the scene
}

constexpr int kRays = 4099;

} // namespace

TEST(DispatchLimits, RaysPerDispatchCapKeepsHitsAndCounters) {
  const PackedScene packed = build_accel(capsule_scene(2000, 11), Method::Masq);
  const std::vector<Ray> rays = random_rays(5, kRays);
  for (const BackendRow& row : backend_table.rows()) {
    if (!row.device_api) continue; // the cpu traces in place: no dispatch
    const std::string name = row.name;
    SCOPED_TRACE(name);
    std::unique_ptr<Backend> be = test::open_or_fail(name, [](const std::string& n) { return make_backend(n); });
    if (!be) continue;
    be->set_scene(packed);
    for (Query q : {Query::Closest, Query::Any}) {
      const Result whole = trace(*be, rays, q);
      ScopedEnv cap("MASQ_MAX_RAYS_PER_DISPATCH", "1000"); // 5 dispatches, the last of 99 rays
      expect_same(whole, trace(*be, rays, q));
    }
    // The knob is read at every trace: a bad value is refused there, naming it.
    ScopedEnv bad("MASQ_MAX_RAYS_PER_DISPATCH", "0");
    try {
      trace(*be, rays, Query::Closest);
      ADD_FAILURE() << "no error for MASQ_MAX_RAYS_PER_DISPATCH=0";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("MASQ_MAX_RAYS_PER_DISPATCH='0'"), std::string::npos) << e.what();
    }
  }
}

TEST(DispatchLimits, BvTracersRaysPerDispatchCapKeepsHitsAndCounters) {
  BvOptions o;
  o.type = BvType::Scb;
  const BvScene bv = build_bv_scene(capsule_scene(2000, 12), o);
  const std::vector<Ray> rays = random_rays(6, kRays);
  for (const char* name : {"vulkan", "opencl"}) {
    SCOPED_TRACE(name);
    std::unique_ptr<BvTracer> t = test::open_or_fail(name, [](const std::string& n) { return make_bv_tracer(n); });
    if (!t) continue;
    t->set_scene(bv);
    const Result whole = trace(*t, rays);
    ScopedEnv cap("MASQ_MAX_RAYS_PER_DISPATCH", "1000");
    expect_same(whole, trace(*t, rays));
  }
}

// One cluster per two capsules: about 3000 cluster BLAS, each once its own allocation
// and submission; 64 live allocations must now hold the scene (rtpipeline: and a hit
// record per BLAS in its binding table).
namespace {
void cluster_scene_within_few_allocations(const std::string& name) {
  SCOPED_TRACE(name);
  std::unique_ptr<Backend> be = test::open_or_fail(name, [](const std::string& n) { return make_backend(n); });
  if (!be) return;
  AccelOptions opt;
  opt.cluster.max_size = 2;
  const PackedScene packed = build_accel(capsule_scene(6000, 13), Method::Cluster, opt);
  ASSERT_GT(vk::plan_ray_query(packed, 1u << 24).blas.size(), 2000u);
  const std::vector<Ray> rays = random_rays(7, kRays);
  be->set_scene(packed);
  const Result free_run = trace(*be, rays, Query::Closest);
  const std::size_t bytes = be->device_bytes();
  {
    ScopedEnv few("MASQ_VK_MAX_ALLOCATIONS", "64");
    be->set_scene(packed);
    expect_same(free_run, trace(*be, rays, Query::Closest));
    EXPECT_EQ(be->device_bytes(), bytes); // the same compacted structures
  }
  // Far too few for the scene arrays alone: one error naming the limit and the knob.
  std::unique_ptr<Backend> fresh = make_backend(name);
  ScopedEnv none("MASQ_VK_MAX_ALLOCATIONS", "4");
  try {
    fresh->set_scene(packed);
    ADD_FAILURE() << "no error with MASQ_VK_MAX_ALLOCATIONS=4";
  } catch (const Error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("maxMemoryAllocationCount"), std::string::npos) << what;
    EXPECT_NE(what.find("MASQ_VK_MAX_ALLOCATIONS"), std::string::npos) << what;
  }
}
} // namespace

TEST(DispatchLimits, DriverTraversalClusterSceneWithinFewAllocations) {
  for (const std::string& name : backend_names())
    if (driver_traversal(name)) cluster_scene_within_few_allocations(name);
}

// Upload and readback are parts of the trace's wall time on the host clock (vulkan:
// host copies inside it; cpu: none).
TEST(DispatchLimits, TraceTimingPartsWithinWallTime) {
  const PackedScene packed = build_accel(capsule_scene(500, 14), Method::Ref);
  const std::vector<Ray> rays = random_rays(8, kRays);
  for (const std::string& name : backend_names()) {
    SCOPED_TRACE(name);
    std::unique_ptr<Backend> be = test::open_or_fail(name, [](const std::string& n) { return make_backend(n); });
    if (!be) continue;
    be->set_scene(packed);
    trace(*be, rays, Query::Closest);
    const TraceTiming t = be->timing();
    EXPECT_GT(t.wall_seconds, 0.0);
    EXPECT_GE(t.upload_seconds, 0.0);
    EXPECT_GE(t.readback_seconds, 0.0);
    EXPECT_LE(t.upload_seconds + t.readback_seconds, t.wall_seconds);
    if (name == "cpu") EXPECT_EQ(t.upload_seconds + t.readback_seconds, 0.0);
    else EXPECT_GT(t.upload_seconds, 0.0);
  }
}
