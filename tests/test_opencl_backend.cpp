// The opencl backend against the cpu backend (the same kernel source compiled as C++),
// plus its error paths. Both run kernels/traverse.h, so this checks the OpenCL dialect
// and the host plumbing (upload, chunking, variants), not the intersectors' accuracy
// (that is the oracle tests' job).
#include "bvh/twolevel/build_accel.h"
#include "host/cpu/cpu_backend.h"
#include "host/opencl/cl_local_size.h"
#include "host/opencl/cl_runtime.h"
#include "host/opencl/opencl_backend.h"
#include "scenes/camera.h"
#include "masq/error.h"
#include "scenes/generators.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <string>
#include <vector>
#include "tests/test_env.h"

namespace {

using namespace masq;
using kernel::Hit;
using kernel::Ray;
using kernel::RayStats;

// Null when OpenCL is missing and MASQ_ALLOW_MISSING_BACKENDS=1 (then the test skips);
// otherwise a missing platform fails: the setup script installs PoCL.
std::unique_ptr<Backend> open_or_skip(std::size_t chunk = masq::kMaxRaysPerDispatch) {
  try {
    return make_opencl_backend(chunk);
  } catch (const BackendUnavailable& e) {
    if (masq::test::missing_backends_allowed()) return nullptr;
    ADD_FAILURE() << e.what() << " (MASQ_ALLOW_MISSING_BACKENDS=1 skips)";
    return nullptr;
  }
}
#define OPEN_OR_SKIP(var, ...)                                    \
  auto var = open_or_skip(__VA_ARGS__);                           \
  if (!var) {                                                     \
    if (HasFailure()) return;                                     \
    GTEST_SKIP() << "no OpenCL platform (MASQ_ALLOW_MISSING_BACKENDS=1)"; \
  }

kernel::WideNode empty_node() {
  kernel::WideNode n{};
  for (int i = 0; i < MASQ_WIDTH; ++i) {
    n.child[i] = 0;
    n.count[i] = -1;
  }
  return n;
}

void set_slot(kernel::WideNode& n, int slot, float lo, float hi, int child, int count) {
  n.lo_x[slot] = n.lo_y[slot] = n.lo_z[slot] = lo;
  n.hi_x[slot] = n.hi_y[slot] = n.hi_z[slot] = hi;
  n.child[slot] = child;
  n.count[slot] = count;
}

void set_identity(float* m) {
  for (int i = 0; i < 12; ++i) m[i] = (i == 0 || i == 5 || i == 10) ? 1.0f : 0.0f;
}

// TLAS root (node 0) -> instance 0 (identity) -> BLAS root (node 1) -> leaf of two
// capsules along x: one at y = 0, z = 0, one at y = 0.5, z = 1.
PackedScene hand_built_scene() {
  PackedScene s;
  s.nodes = {empty_node(), empty_node()};
  set_slot(s.nodes[0], 0, -2.0f, 2.0f, 0, 1);
  set_slot(s.nodes[1], 0, -2.0f, 2.0f, 1, 2);
  s.refs = {0, 0, 1};
  kernel::Instance inst{};
  set_identity(inst.world_to_object);
  inst.blas_root = 1;
  inst.geom = 0;
  inst.prim = -1;
  inst.scene_inst = 0;
  s.instances = {inst};
  kernel::Frame frame{};
  set_identity(frame.world_to_object);
  s.frames = {frame};
  s.geoms = {kernel::Geometry{MASQ_PRIM_CAPSULE, 0, 2, 0}};
  s.capsules = {kernel::Capsule{{-1.0f, 0.0f, 0.0f}, 0.1f, {1.0f, 0.0f, 0.0f}, 0.0f},
                kernel::Capsule{{-1.0f, 0.5f, 1.0f}, 0.2f, {1.0f, 0.5f, 1.0f}, 0.0f}};
  s.tlas_root = 0;
  s.features.prims[MASQ_PRIM_CAPSULE] = true;
  return s;
}

std::vector<Ray> grid_rays(int w, int h, float extent) {
  std::vector<Ray> rays;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      float px = -extent + 2.0f * extent * (x + 0.5f) / w;
      float py = -extent + 2.0f * extent * (y + 0.5f) / h;
      rays.push_back(Ray{{px, py, -5.0f}, 0.0f, {0.0f, 0.0f, 1.0f}, 1e30f});
    }
  return rays;
}

struct Traced {
  std::vector<Hit> hits;
  std::vector<RayStats> stats;
};

Traced run(Backend& b, const PackedScene& scene, const std::vector<Ray>& rays, bool with_stats) {
  Traced t;
  t.hits.resize(rays.size());
  if (with_stats) t.stats.resize(rays.size());
  b.set_scene(scene);
  b.trace(rays, t.hits, t.stats);
  return t;
}

// Hit/miss or primitive disagreements; where both hit the same primitive, t must agree
// to 1e-4 relative (both are fp32 evaluations of the same code).
int disagreements(const std::vector<Hit>& a, const std::vector<Hit>& b) {
  int bad = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if ((a[i].prim >= 0) != (b[i].prim >= 0) || a[i].prim != b[i].prim || a[i].geom != b[i].geom ||
        a[i].inst != b[i].inst) {
      ++bad;
      continue;
    }
    if (a[i].prim < 0) continue;
    EXPECT_NEAR(a[i].t, b[i].t, 1e-4f * std::fabs(b[i].t)) << "ray " << i;
  }
  return bad;
}

TEST(OpenClBackend, HandBuiltSceneMatchesCpuAndGeometry) {
  OPEN_OR_SKIP(ocl);
  EXPECT_EQ(ocl->name(), "opencl");
  EXPECT_FALSE(ocl->device_name().empty());
  const PackedScene scene = hand_built_scene();
  std::vector<Ray> rays = grid_rays(64, 64, 1.5f);
  rays.push_back(Ray{{0.0f, 0.0f, -5.0f}, 0.0f, {0.0f, 0.0f, 1.0f}, 1e30f}); // hits capsule 0 at 4.9
  rays.push_back(Ray{{0.0f, 0.5f, -5.0f}, 0.0f, {0.0f, 0.0f, 2.0f}, 1e30f}); // capsule 1 at (6-0.2)/2
  rays.push_back(Ray{{0.0f, 0.0f, -5.0f}, 0.0f, {0.0f, 0.0f, 0.0f}, 1e30f}); // invalid: misses
  const Traced o = run(*ocl, scene, rays, false);
  const std::size_t n = rays.size();
  EXPECT_EQ(o.hits[n - 3].prim, 0);
  EXPECT_NEAR(o.hits[n - 3].t, 4.9f, 1e-5f);
  EXPECT_NEAR(o.hits[n - 3].normal[2], -1.0f, 1e-5f);
  EXPECT_EQ(o.hits[n - 2].prim, 1);
  EXPECT_NEAR(o.hits[n - 2].t, 2.9f, 1e-5f);
  EXPECT_LT(o.hits[n - 1].prim, 0);
  EXPECT_EQ(ocl->device_bytes(), 2 * sizeof(kernel::WideNode) + 16 + sizeof(kernel::Instance) +
                                     sizeof(kernel::Frame) + sizeof(kernel::Geometry) + 16 +
                                     2 * sizeof(kernel::Capsule) + 4 * 16 + // empty cone/sphere/curve/ribbon dummies
                                     2 * 16); // and compact masquerade entries and owners
  auto cpu = make_cpu_backend();
  const Traced c = run(*cpu, scene, rays, false);
  EXPECT_EQ(disagreements(o.hits, c.hits), 0);
}

TEST(OpenClBackend, ChunkedDispatchEqualsSingleDispatch) {
  OPEN_OR_SKIP(small, 1000);
  OPEN_OR_SKIP(big);
  const PackedScene scene = hand_built_scene();
  const std::vector<Ray> rays = grid_rays(77, 53, 1.5f); // 4081 rays: 5 chunks, last partial
  const Traced a = run(*small, scene, rays, true);
  const Traced b = run(*big, scene, rays, true);
  for (std::size_t i = 0; i < rays.size(); ++i) {
    ASSERT_EQ(a.hits[i].prim, b.hits[i].prim) << "ray " << i;
    ASSERT_EQ(a.hits[i].t, b.hits[i].t) << "ray " << i;
    ASSERT_EQ(a.stats[i].isect_calls, b.stats[i].isect_calls) << "ray " << i;
  }
}

class OpenClDefaultScene : public ::testing::TestWithParam<Method> {};

// The default scene (capsule bundle over a triangle ground plane) through both
// backends, counter-free and stats variants.
TEST_P(OpenClDefaultScene, MatchesCpuBackend) {
  OPEN_OR_SKIP(ocl);
  const Scene scene = make_default_scene();
  const PackedScene packed = build_accel(scene, GetParam());
  const std::vector<Ray> rays = make_camera_rays(scene.camera, 192, 192);
  const Traced plain = run(*ocl, packed, rays, false);
  const Traced stats = run(*ocl, packed, rays, true);
  auto cpu = make_cpu_backend();
  const Traced ref = run(*cpu, packed, rays, true);

  // Same device, same program apart from the counters: identical hits.
  for (std::size_t i = 0; i < rays.size(); ++i) {
    ASSERT_EQ(plain.hits[i].prim, stats.hits[i].prim) << "ray " << i;
    ASSERT_EQ(plain.hits[i].t, stats.hits[i].t) << "ray " << i;
  }
  // Against C++: the OpenCL compiler contracts a*b+c into fma (OpenCL C allows it by
  // default; the C++ build does not), so a ray grazing a capsule's silhouette can hit
  // it on one backend and pass it on the other. Measured with PoCL: 5 of 1M camera
  // rays, all silhouette grazes, and 0 with `#pragma OPENCL FP_CONTRACT OFF`. Allow a
  // handful in 36,864 rays.
  int hits = 0;
  for (const Hit& h : plain.hits) hits += h.prim >= 0;
  EXPECT_GT(hits, 1000);
  EXPECT_LE(disagreements(plain.hits, ref.hits), 8);

  long long tlas = 0, isect = 0, cpu_isect = 0;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    tlas += stats.stats[i].tlas_nodes;
    isect += stats.stats[i].isect_calls;
    cpu_isect += ref.stats[i].isect_calls;
    if (stats.hits[i].prim >= 0) {
      ASSERT_GT(stats.stats[i].isect_calls, 0) << "ray " << i;
    }
  }
  EXPECT_GT(tlas, 0);
  EXPECT_GT(isect, 0);
  EXPECT_NEAR(static_cast<double>(isect), static_cast<double>(cpu_isect), 0.001 * cpu_isect);
  const TraceTiming t = ocl->timing();
  EXPECT_GT(t.trace_seconds, 0.0);
  EXPECT_GT(t.compile_seconds, 0.0);
  EXPECT_GE(ocl->device_bytes(), packed.acceleration_bytes() + packed.primitive_bytes());
}

INSTANTIATE_TEST_SUITE_P(Methods, OpenClDefaultScene, ::testing::Values(Method::Ref, Method::Masq),
                         [](const auto& p) { return std::string(method_name(p.param)); });

TEST(OpenClBackend, BuildFailureNamesFileAndLine) {
  opencl::Runtime rt;
  try {
    rt = opencl::open_runtime();
  } catch (const BackendUnavailable& e) {
    if (masq::test::missing_backends_allowed()) GTEST_SKIP() << e.what();
    FAIL() << e.what();
  }
  const std::string broken = "#line 7 \"kernels/broken.h\"\n__kernel void k(__global int* p) { p[0] = ; }\n";
  try {
    opencl::build_program(rt, broken, opencl::base_build_options(rt), "kernels/broken.cl");
    FAIL() << "broken source built";
  } catch (const Error& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("kernels/broken.cl"), std::string::npos) << msg;
    EXPECT_NE(msg.find("CL_BUILD_PROGRAM_FAILURE"), std::string::npos) << msg;
    EXPECT_NE(msg.find("kernels/broken.h:7"), std::string::npos) << msg;
    EXPECT_EQ(msg.find('\n'), std::string::npos) << "one line: " << msg;
  }
}

TEST(OpenClBackend, MisuseIsAnError) {
  OPEN_OR_SKIP(ocl);
  std::vector<Ray> rays(4);
  std::vector<Hit> hits(4), short_hits(3);
  std::vector<RayStats> short_stats(2);
  EXPECT_THROW(ocl->trace(rays, hits, {}), Error); // no scene yet
  PackedScene bad = hand_built_scene();
  bad.tlas_root = 5;
  EXPECT_THROW(ocl->set_scene(bad), Error);
  ocl->set_scene(hand_built_scene());
  EXPECT_THROW(ocl->trace(rays, short_hits, {}), Error);
  EXPECT_THROW(ocl->trace(rays, hits, short_stats), Error);
  ocl->trace({}, {}, {}); // empty batch is fine
  EXPECT_EQ(ocl->timing().trace_seconds, 0.0);
}

// Work-group shapes for the kernel limits of real devices (host/opencl/cl_local_size.h):
// GPUs get 64 in whole warps or wavefronts within the kernel's limit; a CPU device keeps
// the runtime's choice over a global size padded to 64.
TEST(OpenclWorkGroup, FitsThePreferredMultipleAndTheLimits) {
  using opencl::fit_work_group;
  EXPECT_EQ(fit_work_group(false, 64, 32, 1024, 1024).local, 64u);  // NVIDIA
  EXPECT_EQ(fit_work_group(false, 64, 64, 256, 1024).local, 64u);   // AMD
  EXPECT_EQ(fit_work_group(false, 64, 48, 1024, 1024).local, 96u);  // whole multiples
  EXPECT_EQ(fit_work_group(false, 64, 32, 40, 1024).local, 32u);    // a kernel limited by its registers
  EXPECT_EQ(fit_work_group(false, 64, 32, 1024, 16).local, 16u);    // below one warp: the limit
  const opencl::WorkGroup cpu = fit_work_group(true, 64, 8, 4096, 4096);
  EXPECT_EQ(cpu.local, 0u);
  EXPECT_EQ(opencl::padded_global(cpu, 65), 128u);
  const opencl::WorkGroup gpu = fit_work_group(false, 64, 32, 1024, 1024);
  EXPECT_EQ(opencl::padded_global(gpu, 1), 64u);
}

} // namespace
