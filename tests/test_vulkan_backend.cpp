// The Vulkan backends against the cpu backend (the same kernel source compiled as C++):
// "vulkan" runs the identical traversal as a compute shader; "rayquery" lets the
// driver's own acceleration structures find the candidates and calls the same
// intersector. Also: stats variants, chunked tracing, and clean errors when a scene
// exceeds the device's limits (lowered through the limit knobs, host/limit_knob.h).
#include "bvh/twolevel/build_accel.h"
#include "host/cpu/cpu_backend.h"
#include "host/vulkan/vk_context.h"
#include "host/vulkan/vulkan_backends.h"
#include "scenes/camera.h"
#include "masq/error.h"
#include "scenes/generators.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <string>
#include <vector>
#include "tests/test_env.h"

namespace {

using namespace masq;
using kernel::Hit;
using kernel::Ray;
using kernel::RayStats;

bool allow_no_vulkan() { return masq::test::missing_backends_allowed(); }

// Null (and the test skips) only when Vulkan is missing and MASQ_ALLOW_MISSING_BACKENDS=1.
std::unique_ptr<Backend> make_or_fail(const std::function<std::unique_ptr<Backend>()>& make) {
  try {
    return make();
  } catch (const BackendUnavailable& e) {
    if (!allow_no_vulkan())
      ADD_FAILURE() << e.what() << " (scripts/setup.sh installs lavapipe; MASQ_ALLOW_MISSING_BACKENDS=1 skips)";
    return nullptr;
  }
}

#define VULKAN_BACKEND_OR_SKIP(var, make)                          \
  std::unique_ptr<Backend> var = make_or_fail(make);               \
  if (!var) {                                                      \
    if (allow_no_vulkan()) GTEST_SKIP() << "no Vulkan driver (MASQ_ALLOW_MISSING_BACKENDS=1)"; \
    return;                                                        \
  }

struct Diff {
  int both_hit = 0;
  int hit_miss = 0;   // one hits, the other misses
  int wrong_prim = 0; // both hit, different prim/geom/inst
  int wrong_t = 0;    // same primitive, t differs by more than 1e-4 relative
  int wrong_normal = 0; // same primitive, normals more than ~0.8 degrees apart
  std::string first;
};

Diff compare(const std::vector<Hit>& want, const std::vector<Hit>& got) {
  Diff d;
  for (std::size_t i = 0; i < want.size(); ++i) {
    const Hit& a = want[i];
    const Hit& b = got[i];
    auto note = [&](int& counter, const char* what) {
      if (counter++ == 0 && d.first.empty())
        d.first = "ray " + std::to_string(i) + ": " + what + " (cpu prim " + std::to_string(a.prim) + " t " +
                  std::to_string(a.t) + ", gpu prim " + std::to_string(b.prim) + " t " + std::to_string(b.t) + ")";
    };
    if ((a.prim < 0) != (b.prim < 0)) {
      note(d.hit_miss, "hit vs miss");
      continue;
    }
    if (a.prim < 0) continue;
    ++d.both_hit;
    if (a.prim != b.prim || a.geom != b.geom || a.inst != b.inst) {
      note(d.wrong_prim, "different primitive");
      continue;
    }
    if (std::abs(double(a.t) - double(b.t)) > 1e-4 * std::abs(double(a.t))) note(d.wrong_t, "t differs");
    double c = double(a.normal[0]) * b.normal[0] + double(a.normal[1]) * b.normal[1] +
               double(a.normal[2]) * b.normal[2];
    if (c < 0.9999) note(d.wrong_normal, "normal differs");
  }
  return d;
}

// Two capsules side by side and one behind, under an identity instance: the smallest
// two-level structure (TLAS root -> instance 0 -> BLAS root leaf of 3 capsules).
PackedScene tiny_scene() {
  PackedScene s;
  s.method = Method::Ref;
  auto empty_node = [] {
    kernel::WideNode n{};
    for (int i = 0; i < MASQ_WIDTH; ++i) n.count[i] = -1;
    return n;
  };
  kernel::WideNode tlas = empty_node();
  kernel::WideNode blas = empty_node();
  const float lo[3] = {-2, -2, -2}, hi[3] = {2, 2, 2};
  for (kernel::WideNode* n : {&tlas, &blas}) {
    n->lo_x[0] = lo[0], n->lo_y[0] = lo[1], n->lo_z[0] = lo[2];
    n->hi_x[0] = hi[0], n->hi_y[0] = hi[1], n->hi_z[0] = hi[2];
  }
  tlas.child[0] = 0, tlas.count[0] = 1; // refs[0]: instance 0
  blas.child[0] = 1, blas.count[0] = 3; // refs[1..3]: capsules 0..2
  s.nodes = {tlas, blas};
  s.refs = {0, 0, 1, 2};
  kernel::Instance inst{};
  inst.world_to_object[0] = inst.world_to_object[5] = inst.world_to_object[10] = 1.0f;
  inst.blas_root = 1, inst.geom = 0, inst.prim = -1, inst.scene_inst = 0;
  s.instances = {inst};
  kernel::Frame f{};
  f.world_to_object[0] = f.world_to_object[5] = f.world_to_object[10] = 1.0f;
  s.frames = {f};
  s.geoms = {kernel::Geometry{MASQ_PRIM_CAPSULE, 0, 3, 0}};
  s.capsules = {kernel::Capsule{{-0.5f, -1.0f, 0.0f}, 0.2f, {-0.5f, 1.0f, 0.0f}, 0.0f},
                kernel::Capsule{{0.5f, -1.0f, 0.2f}, 0.3f, {0.6f, 1.0f, 0.0f}, 0.0f},
                kernel::Capsule{{-1.0f, 0.0f, 1.0f}, 0.25f, {1.0f, 0.1f, 1.0f}, 0.0f}};
  s.tlas_root = 0;
  s.features.prims[MASQ_PRIM_CAPSULE] = true;
  s.frame_object_to_world = {Mat3x4f{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0}};
  s.tlas_leaf_order = {0};
  s.geometry_leaf_order = {{2, 0, 1}}; // not the identity: exercises the id map
  return s;
}

// Orthographic rays along +z over [-1.5, 1.5]^2, from z = -5.
std::vector<Ray> grid_rays(int n) {
  std::vector<Ray> rays;
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      Ray r{};
      r.org[0] = -1.5f + 3.0f * (float(x) + 0.5f) / float(n);
      r.org[1] = -1.5f + 3.0f * (float(y) + 0.5f) / float(n);
      r.org[2] = -5.0f;
      r.dir[2] = 1.0f;
      r.tmax = 1e30f;
      rays.push_back(r);
    }
  return rays;
}

std::vector<Hit> trace(Backend& be, const std::vector<Ray>& rays) {
  std::vector<Hit> hits(rays.size());
  be.trace(rays, hits, {});
  return hits;
}

TEST(VulkanBackend, TinySceneMatchesCpu) {
  VULKAN_BACKEND_OR_SKIP(vulkan, make_vulkan_backend);
  VULKAN_BACKEND_OR_SKIP(rayquery, make_rayquery_backend);
  VULKAN_BACKEND_OR_SKIP(rtpipeline, make_rtpipeline_backend);
  auto cpu = make_cpu_backend();
  PackedScene s = tiny_scene();
  std::vector<Ray> rays = grid_rays(64);
  cpu->set_scene(s);
  std::vector<Hit> want = trace(*cpu, rays);
  for (Backend* be : {vulkan.get(), rayquery.get(), rtpipeline.get()}) {
    SCOPED_TRACE(be->name());
    be->set_scene(s);
    Diff d = compare(want, trace(*be, rays));
    EXPECT_GT(d.both_hit, 500);
    EXPECT_EQ(d.hit_miss, 0) << d.first;
    EXPECT_EQ(d.wrong_prim, 0) << d.first;
    EXPECT_EQ(d.wrong_t, 0) << d.first;
    EXPECT_EQ(d.wrong_normal, 0) << d.first;
    EXPECT_GT(be->device_bytes(), 0u);
    EXPECT_FALSE(be->device_name().empty());
  }
}

TEST(VulkanBackend, EmptySceneAndInvalidRaysMiss) {
  VULKAN_BACKEND_OR_SKIP(vulkan, make_vulkan_backend);
  VULKAN_BACKEND_OR_SKIP(rayquery, make_rayquery_backend);
  VULKAN_BACKEND_OR_SKIP(rtpipeline, make_rtpipeline_backend);
  std::vector<Ray> rays = grid_rays(4);
  rays[0].dir[0] = std::nanf("");
  rays[1].dir[2] = 0.0f;      // zero direction
  rays[2].tmin = 10.0f;       // empty interval
  rays[2].tmax = 1.0f;
  rays[3].org[1] = INFINITY;
  for (Backend* be : {vulkan.get(), rayquery.get(), rtpipeline.get()}) {
    SCOPED_TRACE(be->name());
    be->set_scene(PackedScene{}); // nothing at all
    for (const Hit& h : trace(*be, rays)) EXPECT_LT(h.prim, 0);
    be->set_scene(tiny_scene());
    std::vector<Hit> hits = trace(*be, rays);
    for (int i = 0; i < 4; ++i) EXPECT_LT(hits[std::size_t(i)].prim, 0) << "invalid ray " << i;
    std::vector<Hit> none;
    EXPECT_NO_THROW(be->trace({}, none, {}));
  }
}

TEST(VulkanBackend, ChunkedTracingMatchesOneChunk) {
  VULKAN_BACKEND_OR_SKIP(vulkan, make_vulkan_backend);
  VULKAN_BACKEND_OR_SKIP(rayquery, make_rayquery_backend);
  VULKAN_BACKEND_OR_SKIP(rtpipeline, make_rtpipeline_backend);
  PackedScene s = tiny_scene();
  std::vector<Ray> rays = grid_rays(40); // 1600 rays
  for (Backend* be : {vulkan.get(), rayquery.get(), rtpipeline.get()}) {
    SCOPED_TRACE(be->name());
    be->set_scene(s);
    std::vector<Hit> whole = trace(*be, rays);
    std::vector<Hit> chunked;
    {
      // 48 * 100 bytes: chunks of 100 rays (the scene arrays still fit).
      test::ScopedEnv binding("MASQ_VK_MAX_BINDING_BYTES", std::to_string(sizeof(Hit) * 100));
      EXPECT_NO_THROW(chunked = trace(*be, rays));
    }
    ASSERT_EQ(chunked.size(), whole.size());
    Diff d = compare(whole, chunked);
    EXPECT_EQ(d.hit_miss + d.wrong_prim + d.wrong_t, 0) << d.first;
  }
}

TEST(VulkanBackend, TooLargeScenesFailCleanly) {
  VULKAN_BACKEND_OR_SKIP(vulkan, make_vulkan_backend);
  VULKAN_BACKEND_OR_SKIP(rayquery, make_rayquery_backend);
  VULKAN_BACKEND_OR_SKIP(rtpipeline, make_rtpipeline_backend);
  PackedScene s = build_accel(make_default_scene(), Method::Masq);
  // Masquerade: 1000+ instances of 64 bytes cannot fit one 16 KiB buffer (nor, for the
  // compute backend, can the nodes). Over one storage binding is not an error (arrays
  // are then read by address, tests/test_large_scenes.cpp); over one allocation is.
  {
    test::ScopedEnv allocation("MASQ_VK_MAX_ALLOCATION_BYTES", std::to_string(16 * 1024));
    for (Backend* be : {vulkan.get(), rayquery.get(), rtpipeline.get()}) {
      try {
        be->set_scene(s);
        ADD_FAILURE() << be->name() << ": no error for a scene over maxMemoryAllocationSize";
      } catch (const Error& e) {
        std::string what = e.what();
        EXPECT_NE(what.find("maxMemoryAllocationSize"), std::string::npos) << what;
        EXPECT_NE(what.find("bytes in one buffer"), std::string::npos) << what;
      }
    }
  }
  // After the failures the backends still work.
  for (Backend* be : {vulkan.get(), rayquery.get(), rtpipeline.get()}) {
    be->set_scene(tiny_scene());
    EXPECT_GT(compare(trace(*be, grid_rays(8)), trace(*be, grid_rays(8))).both_hit, 0);
  }
}

// The default scene (1000 capsules r = 0.002 over a 2-triangle ground plane) with both
// methods. "vulkan" runs the same code as cpu and must agree exactly up to rounding.
// "rayquery" may differ on a handful of silhouette rays: for the reference method the
// driver computes the object-space ray itself (its own fp32 inverse of the instance
// transform), so grazing rays can flip hit/miss or pick the other of two capsules that
// the ray touches at nearly the same t; triangle hits come from the driver's own
// (watertight but differently rounded) triangle test.
TEST(VulkanBackend, DefaultSceneMatchesCpu) {
  VULKAN_BACKEND_OR_SKIP(vulkan, make_vulkan_backend);
  VULKAN_BACKEND_OR_SKIP(rayquery, make_rayquery_backend);
  VULKAN_BACKEND_OR_SKIP(rtpipeline, make_rtpipeline_backend);
  auto cpu = make_cpu_backend();
  Scene scene = make_default_scene();
  std::vector<Ray> rays = make_camera_rays(scene.camera, 256, 256);
  for (Method m : {Method::Ref, Method::Masq}) {
    PackedScene ps = build_accel(scene, m);
    cpu->set_scene(ps);
    std::vector<Hit> want = trace(*cpu, rays);
    for (Backend* be : {vulkan.get(), rayquery.get(), rtpipeline.get()}) {
      SCOPED_TRACE(be->name() + " " + method_name(m));
      be->set_scene(ps);
      std::vector<Hit> got(rays.size());
      std::vector<RayStats> stats(rays.size());
      be->trace(rays, got, stats); // stats variant (JIT) first
      double stats_s = be->timing().trace_seconds;
      got = trace(*be, rays);
      TraceTiming t = be->timing();
      Diff d = compare(want, got);
      const int allowed = be->name() == "vulkan" ? 2 : 8;
      EXPECT_GT(d.both_hit, int(rays.size() / 20));
      EXPECT_LE(d.hit_miss, allowed) << d.first;
      EXPECT_LE(d.wrong_prim, allowed) << d.first;
      EXPECT_LE(d.wrong_t, allowed) << d.first;
      EXPECT_LE(d.wrong_normal, allowed) << d.first;
      long long calls = 0, tlas = 0;
      for (const RayStats& st : stats) {
        calls += st.isect_calls;
        tlas += st.tlas_nodes;
      }
      EXPECT_GT(calls, 0);
      if (be->name() == "vulkan") EXPECT_GT(tlas, 0);
      else EXPECT_EQ(stats[0].tlas_nodes, -1);
      std::printf("[ %-8s %-4s ] %zu rays: %d both hit, %d hit/miss, %d prim, %d t, %d normal differ; "
                  "%.2f Mrays/s (stats variant %.2f), scene %.3f s, compile %.3f s, %zu device bytes, "
                  "%.3f isect calls/ray\n",
                  be->name().c_str(), method_name(m), rays.size(), d.both_hit, d.hit_miss, d.wrong_prim,
                  d.wrong_t, d.wrong_normal, double(rays.size()) / t.trace_seconds * 1e-6,
                  double(rays.size()) / stats_s * 1e-6, t.scene_seconds, t.compile_seconds,
                  be->device_bytes(), double(calls) / double(rays.size()));
    }
  }
}

} // namespace

namespace {

// rtpipeline and rayquery traverse the same driver structures (host/vulkan/driver_scene.h):
// the intersection-shader invocations of the one and the candidates the other's proceed
// loop hands the shader are the same boxes' hits. A driver may order the two paths'
// traversals differently (the nearest hit so far prunes what is left), so the totals are
// compared within 10%; on lavapipe, one traversal serves both, and they are equal.
TEST(VulkanBackend, RtPipelineCallsTheIntersectorsRayQueryCalls) {
  VULKAN_BACKEND_OR_SKIP(rayquery, make_rayquery_backend);
  VULKAN_BACKEND_OR_SKIP(rtpipeline, make_rtpipeline_backend);
  Scene scene = make_default_scene();
  std::vector<Ray> rays = make_camera_rays(scene.camera, 128, 96);
  for (Method m : {Method::Ref, Method::Masq, Method::Cluster}) {
    SCOPED_TRACE(method_name(m));
    PackedScene ps = build_accel(scene, m);
    long long calls[2] = {0, 0};
    std::vector<Hit> hits[2];
    int k = 0;
    for (Backend* be : {rayquery.get(), rtpipeline.get()}) {
      be->set_scene(ps);
      hits[k].resize(rays.size());
      std::vector<RayStats> stats(rays.size());
      be->trace(rays, hits[k], stats);
      for (const RayStats& st : stats) {
        EXPECT_EQ(st.tlas_nodes, -1);
        calls[k] += st.isect_calls;
      }
      ++k;
    }
    EXPECT_GT(calls[0], 0);
    EXPECT_NEAR(double(calls[1]), double(calls[0]), 0.1 * double(calls[0]));
    Diff d = compare(hits[0], hits[1]);
    EXPECT_EQ(d.hit_miss + d.wrong_prim, 0) << d.first;
    std::printf("[ %-7s ] intersector calls per ray: rayquery %.3f, rtpipeline %.3f\n", method_name(m),
                double(calls[0]) / double(rays.size()), double(calls[1]) / double(rays.size()));
  }
}

// Two backend objects on one device (the bench's slots) run the same pipeline for the same
// variant: the second makes nothing new, traces the same bits, and a variant the second
// asks for first is the one the first then finds (host/vulkan/vk_shared_objects.h).
TEST(VulkanBackend, BackendObjectsOnOneDeviceShareTheirPipelines) {
  struct Kind {
    const char* name;
    std::unique_ptr<Backend> (*make)();
    DeviceNeed need;
  };
  const Kind kinds[] = {{"vulkan", make_vulkan_backend, DeviceNeed::Compute},
                        {"rayquery", make_rayquery_backend, DeviceNeed::RayQuery},
                        {"rtpipeline", make_rtpipeline_backend, DeviceNeed::RayPipeline}};
  Scene scene = make_default_scene();
  PackedScene ps = build_accel(scene, Method::Masq);
  std::vector<Ray> rays = make_camera_rays(scene.camera, 32, 24);
  for (const Kind& kind : kinds) {
    SCOPED_TRACE(kind.name);
    VULKAN_BACKEND_OR_SKIP(first, kind.make);
    VULKAN_BACKEND_OR_SKIP(second, kind.make);
    std::shared_ptr<vk::Context> ctx = vk::Context::get(kind.name, kind.need); // the one both hold
    std::vector<Hit> a(rays.size()), b(rays.size());
    first->set_scene(ps);
    second->set_scene(ps);
    first->trace(rays, a, {});
    const std::size_t made = ctx->shared().size();
    second->trace(rays, b, {});
    EXPECT_EQ(ctx->shared().size(), made) << "the second object compiled the variant again";
    Diff d = compare(a, b);
    EXPECT_EQ(d.hit_miss + d.wrong_prim + d.wrong_t, 0) << d.first;
    std::vector<RayStats> stats(rays.size());
    second->trace(rays, b, stats, Query::Any); // a variant neither has run yet
    EXPECT_EQ(ctx->shared().size(), made + 1);
    first->trace(rays, a, stats, Query::Any);
    EXPECT_EQ(ctx->shared().size(), made + 1);
  }
}

} // namespace
