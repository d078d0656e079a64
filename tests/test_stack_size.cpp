// Traversal stacks sized from the scene's trees (kernels/variant_table.h MASQ_TLAS_STACK,
// MASQ_BLAS_STACK; host/stack_size.h): the rounding, the one clear error when a tree
// needs more than the largest stack (instead of dropped nodes and missed hits), and the
// same hits and per-ray counters with the sized stacks as with the largest on every
// backend. (The builders' need itself: EveryFormat.StackBoundHoldsAndIsReached in
// test_node_formats.cpp; the bv tree's: BvStack.* here.)
#include "bvh/bv/bv_scene.h"
#include "bvh/twolevel/build_accel.h"
#include "host/backend.h"
#include "host/bv_tracer.h"
#include "host/scene_variant.h"
#include "host/stack_size.h"
#include "scenes/camera.h"
#include "scenes/generators.h"
#include "tests/random_rays.h"
#include "tests/test_env.h"
#include <gtest/gtest.h>

using namespace masq;

namespace {

std::unique_ptr<Backend> open_backend(const std::string& name) {
  return test::open_or_fail(name, [](const std::string& n) { return make_backend(n); });
}

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(StackSize, RoundsUpToTheFewSizes) {
  EXPECT_EQ(kernel_stack_size(0, "BLAS"), 8);
  EXPECT_EQ(kernel_stack_size(8, "BLAS"), 8);
  EXPECT_EQ(kernel_stack_size(9, "BLAS"), 16);
  EXPECT_EQ(kernel_stack_size(25, "BLAS"), 32);
  EXPECT_EQ(kernel_stack_size(33, "BLAS"), 48);
  EXPECT_EQ(kernel_stack_size(MASQ_STACK_MAX, "BLAS"), MASQ_STACK_MAX);
  EXPECT_EQ(stack_bytes(8, 16), 192);
}

TEST(StackSize, MoreThanTheLargestIsOneErrorNamingTheTree) {
  const std::string e = error_of([] { kernel_stack_size(MASQ_STACK_MAX + 1, "TLAS"); });
  EXPECT_NE(e.find("TLAS"), std::string::npos) << e;
  EXPECT_NE(e.find(std::to_string(MASQ_STACK_MAX + 1)), std::string::npos) << e;
  EXPECT_NE(e.find(std::to_string(MASQ_STACK_MAX)), std::string::npos) << e;
  KernelFeatures f;
  f.blas_stack.entries = 100;
  const std::string v = error_of([&] { kernel_variant(f, {}); });
  EXPECT_NE(v.find("BLAS traversal needs 100"), std::string::npos) << v;
}

TEST(StackSize, UnknownNeedGetsTheLargestStack) {
  const KernelVariant v = kernel_variant(KernelFeatures{}, {});
  EXPECT_EQ(v.tlas_stack, MASQ_STACK_MAX);
  EXPECT_EQ(v.blas_stack, MASQ_STACK_MAX);
}

// A scene whose trees claim more than the largest stack (as a scene from elsewhere than
// the builders might): every traversing backend refuses to trace it, naming the need.
TEST(StackSize, EveryBackendRefusesASceneThatNeedsMore) {
  Scene s = make_default_scene();
  PackedScene ps = build_accel(s, Method::Ref);
  ps.features.blas_stack.entries = MASQ_STACK_MAX + 7;
  std::vector<kernel::Ray> rays = make_camera_rays(s.camera, 4, 4);
  for (const std::string& name : backend_names()) {
    if (driver_traversal(name)) continue; // no kernel stacks // the driver traverses: it has no kernel stack
    std::unique_ptr<Backend> be = open_backend(name);
    if (!be) continue;
    std::vector<kernel::Hit> hits(rays.size());
    const std::string e = error_of([&] {
      be->set_scene(ps);
      be->trace(rays, hits, {});
    });
    EXPECT_NE(e.find("needs " + std::to_string(MASQ_STACK_MAX + 7) + " stack entries"), std::string::npos)
        << name << ": " << e;
  }
}

// The default scene (every method with its own stacks) gets stacks well below the largest, and
// each backend returns the same hits and counters with them as with the largest.
TEST(StackSize, SizedStacksGiveTheLargestStacksHitsAndCounters) {
  Scene s = make_default_scene();
  std::vector<kernel::Ray> rays = make_camera_rays(s.camera, 32, 24);
  std::vector<kernel::Ray> extra = test::random_rays(7, 800);
  rays.insert(rays.end(), extra.begin(), extra.end());
  for (const std::string& name : backend_names()) {
    if (driver_traversal(name)) continue; // no kernel stacks
    std::unique_ptr<Backend> be = open_backend(name);
    if (!be) continue;
    for (Method m : {Method::Ref, Method::Masq, Method::Cluster}) {
      SCOPED_TRACE(name + " " + method_name(m));
      PackedScene sized = build_accel(s, m);
      EXPECT_LT(sized.features.tlas_stack.entries, MASQ_STACK_MAX / 2);
      EXPECT_LT(sized.features.blas_stack.entries, MASQ_STACK_MAX / 2);
      PackedScene largest = sized;
      largest.features.tlas_stack.entries = largest.features.blas_stack.entries = MASQ_STACK_MAX;
      std::vector<kernel::Hit> h0(rays.size()), h1(rays.size());
      std::vector<kernel::RayStats> s0(rays.size()), s1(rays.size());
      be->set_scene(largest);
      be->trace(rays, h0, s0);
      be->set_scene(sized);
      be->trace(rays, h1, s1);
      int differ = 0;
      for (std::size_t i = 0; i < rays.size(); ++i)
        differ += h0[i].prim != h1[i].prim || h0[i].inst != h1[i].inst || h0[i].t != h1[i].t ||
                  s0[i].tlas_nodes != s1[i].tlas_nodes || s0[i].blas_nodes != s1[i].blas_nodes ||
                  s0[i].isect_calls != s1[i].isect_calls || s0[i].transforms != s1[i].transforms;
      EXPECT_EQ(differ, 0) << "rays whose hit or counters differ";
    }
  }
}

// The bv tree's stack holds at most its depth (kernels/bv_traverse.h).
TEST(BvStack, NeedIsTheTreeDepth) {
  Scene s = make_default_scene();
  BvOptions o;
  BvScene bs = build_bv_scene(s, o);
  EXPECT_EQ(bs.prims.features.blas_stack.entries, bs.stats.depth);
  EXPECT_LE(bs.stats.depth, MASQ_STACK_MAX);
}

// The bv tracers with the depth-sized stack return what they return with the largest.
TEST(BvStack, SizedStackGivesTheLargestStacksHitsAndCounters) {
  Scene s = make_default_scene();
  std::vector<kernel::Ray> rays = make_camera_rays(s.camera, 32, 24);
  const BvScene sized = build_bv_scene(s);
  BvScene largest = sized;
  largest.prims.features.blas_stack.entries = MASQ_STACK_MAX;
  ASSERT_LT(kernel_stack_size(sized.prims.features.blas_stack.entries, "bv"), MASQ_STACK_MAX);
  for (const std::string& name : bv_backend_names()) {
    SCOPED_TRACE(name);
    std::unique_ptr<BvTracer> bt = test::open_or_fail(name, [](const std::string& n) { return make_bv_tracer(n); });
    if (!bt) continue;
    std::vector<kernel::Hit> h0(rays.size()), h1(rays.size());
    std::vector<kernel::RayStats> s0(rays.size()), s1(rays.size());
    bt->set_scene(largest);
    bt->trace(rays, h0, s0);
    bt->set_scene(sized);
    bt->trace(rays, h1, s1);
    int differ = 0;
    for (std::size_t i = 0; i < rays.size(); ++i)
      differ += h0[i].prim != h1[i].prim || h0[i].t != h1[i].t || s0[i].tlas_nodes != s1[i].tlas_nodes ||
                s0[i].blas_nodes != s1[i].blas_nodes || s0[i].isect_calls != s1[i].isect_calls;
    EXPECT_EQ(differ, 0) << "rays whose hit or counters differ";
  }
}

} // namespace
