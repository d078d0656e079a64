// Scenes beyond the driver's limits, made small by lowering the limits with the
// environment knobs of host/limit_knob.h:
//  - vulkan and rayquery with MASQ_VK_MAX_BINDING_BYTES below the scene's arrays: the
//    arrays are read through buffer device addresses (kernels/kernel_data.h);
//  - rayquery with MASQ_RQ_MAX_INSTANCES / MASQ_RQ_MAX_PRIMITIVES below the scene's
//    instance and primitive counts: several TLAS and BLAS parts;
// each must give the cpu backend's hits (closest: same primitive, geometry, instance and
// t; any-hit: same occlusion, and for the vulkan kernel the same hit). Before these
// paths existed such scenes were refused (tests/test_vulkan_backend.cpp keeps that error
// for arrays over one allocation, MASQ_VK_MAX_ALLOCATION_BYTES, tested here too).
#include "bvh/twolevel/build_accel.h"
#include "host/backend.h"
#include "host/bv_tracer.h"
#include "host/scene_variant.h"
#include "host/vulkan/rayquery_plan.h"
#include "host/vulkan/rt_pipeline.h"
#include "host/vulkan/trace_dispatch.h"
#include "host/vulkan/vulkan_backends.h"
#include "bvh/bv/bv_scene.h"
#include "scenes/camera.h"
#include "scenes/generators.h"
#include <gtest/gtest.h>
#include <algorithm>
#include <cstdlib>
#include <random>
#include <string>
#include "tests/random_affine.h"
#include "tests/test_env.h"

using namespace masq;
using kernel::Hit;
using kernel::Ray;

namespace {

using masq::test::ScopedEnv;

std::unique_ptr<Backend> backend_or_fail(const std::string& name, std::string* why = nullptr) {
  return masq::test::open_or_fail(name, [](const std::string& n) { return make_backend(n); }, why);
}

// Primitives of `type` under three random instances, beside a triangle mesh.
Scene random_scene(PrimType type, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  Scene s;
  s.name = std::string("random ") + prim_type_key(type);
  s.geometries.push_back(make_random_geometry(type, 200, 0.004f, 0.05f, 1.0, seed));
  s.geometries.push_back(make_random_mesh(128, 1.0, seed + 1));
  for (int i = 0; i < 3; ++i) s.instances.push_back({0, masq::test::random_affine(rng)});
  s.instances.push_back({1, masq::test::random_affine(rng)});
  return s;
}

std::vector<Ray> random_rays(std::uint64_t seed, int n) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<Ray> rays;
  for (int i = 0; i < n; ++i) {
    glm::dvec3 from = glm::normalize(glm::dvec3(u(rng), u(rng), u(rng))) * 5.0;
    glm::dvec3 to = glm::dvec3(u(rng), u(rng), u(rng)) * 1.5;
    rays.push_back(make_ray(from, to - from));
  }
  return rays;
}

std::vector<Hit> trace(Backend& be, const std::vector<Ray>& rays, Query q) {
  std::vector<Hit> hits(rays.size());
  be.trace(rays, hits, {}, q);
  return hits;
}

struct Diff {
  int hits = 0, hit_miss = 0, wrong_prim = 0, wrong_t = 0;
  std::string first;
};

// same_prim false (ray query any-hit: the driver's traversal order decides which
// occluder is found): only hit vs miss is compared.
Diff compare(const std::vector<Hit>& want, const std::vector<Hit>& got, bool same_prim) {
  Diff d;
  for (std::size_t i = 0; i < want.size(); ++i) {
    const Hit& a = want[i];
    const Hit& b = got[i];
    auto note = [&](int& n, const char* what) {
      if (n++ == 0 && d.first.empty())
        d.first = "ray " + std::to_string(i) + ": " + what + " (cpu prim " + std::to_string(a.prim) + " geom " +
                  std::to_string(a.geom) + " inst " + std::to_string(a.inst) + " t " + std::to_string(a.t) +
                  "; got prim " + std::to_string(b.prim) + " geom " + std::to_string(b.geom) + " inst " +
                  std::to_string(b.inst) + " t " + std::to_string(b.t) + ")";
    };
    if ((a.prim < 0) != (b.prim < 0)) {
      note(d.hit_miss, "hit vs miss");
      continue;
    }
    if (a.prim < 0 || !same_prim) continue;
    ++d.hits;
    if (a.prim != b.prim || a.geom != b.geom || a.inst != b.inst) note(d.wrong_prim, "different primitive");
    else if (std::abs(double(a.t) - double(b.t)) > 1e-4 * std::abs(double(a.t))) note(d.wrong_t, "t differs");
  }
  return d;
}

// Every method on `backend` under the knobs the caller set, against the cpu backend
// (no knobs apply to it) on capsules and curves. "" when it ran, else why the backend
// did not open (a test of it alone skips with that).
std::string check_against_cpu(const std::string& backend,
                              const std::vector<std::pair<const char*, std::string>>& knobs) {
  std::string why;
  std::unique_ptr<Backend> be = backend_or_fail(backend, &why);
  if (!be) return why;
  std::unique_ptr<Backend> cpu = make_backend("cpu");
  std::vector<Ray> rays = random_rays(7, 2048);
  for (PrimType type : {PrimType::Capsule, PrimType::Curve}) {
    Scene scene = random_scene(type, 40 + std::uint64_t(type));
    for (Method m : {Method::Ref, Method::Masq, Method::Cluster, Method::Auto}) {
      PackedScene packed = build_accel(scene, m);
      cpu->set_scene(packed);
      std::vector<Hit> closest = trace(*cpu, rays, Query::Closest);
      std::vector<Hit> any = trace(*cpu, rays, Query::Any);
      std::vector<std::unique_ptr<ScopedEnv>> set;
      for (const auto& [name, value] : knobs) set.push_back(std::make_unique<ScopedEnv>(name, value));
      SCOPED_TRACE(backend + " " + method_name(m) + " on " + scene.name);
      be->set_scene(packed);
      Diff c = compare(closest, trace(*be, rays, Query::Closest), true);
      EXPECT_GT(c.hits, 100);
      EXPECT_EQ(c.hit_miss + c.wrong_prim + c.wrong_t, 0) << "closest: " << c.first;
      // The vulkan kernel is the cpu's traversal: the same first hit. Ray query: the
      // same occlusion.
      Diff a = compare(any, trace(*be, rays, Query::Any), backend == "vulkan");
      EXPECT_EQ(a.hit_miss + a.wrong_prim + a.wrong_t, 0) << "any hit: " << a.first;
    }
  }
  return "";
}

} // namespace

// 4 KiB per binding: the capsule, curve, node and instance arrays of these scenes all
// exceed it, and rays go in chunks of 85.
TEST(LargeScenes, VulkanArraysByAddressMatchCpu) {
  if (std::string why = check_against_cpu("vulkan", {{"MASQ_VK_MAX_BINDING_BYTES", "4096"}}); !why.empty())
    GTEST_SKIP() << why;
}

// The vulkan backend reads every scene by address where it can (MASQ_VK_ADDRESSING
// unset); its descriptor-bound path, for devices without bufferDeviceAddress, must
// give the same hits.
TEST(LargeScenes, VulkanBoundArraysMatchCpu) {
  if (std::string why = check_against_cpu("vulkan", {{"MASQ_VK_ADDRESSING", "bound"}}); !why.empty())
    GTEST_SKIP() << why;
}

TEST(LargeScenes, VulkanAddressingKnobRejectsOtherValues) {
  std::string why;
  std::unique_ptr<Backend> be = backend_or_fail("vulkan", &why);
  if (!be) GTEST_SKIP() << why;
  ScopedEnv k("MASQ_VK_ADDRESSING", "fast");
  try {
    be->set_scene(build_accel(random_scene(PrimType::Capsule, 3), Method::Ref));
    ADD_FAILURE() << "no error for MASQ_VK_ADDRESSING=fast";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("MASQ_VK_ADDRESSING='fast'"), std::string::npos) << e.what();
  }
}

// The backends the driver traverses for (rayquery, rtpipeline) share the structures and
// their splitting (host/vulkan/driver_scene.h); each is checked.
std::vector<std::string> driver_backends() {
  std::vector<std::string> out;
  for (const std::string& name : backend_names())
    if (driver_traversal(name)) out.push_back(name);
  return out;
}

TEST(LargeScenes, DriverTraversalArraysByAddressMatchCpu) {
  for (const std::string& name : driver_backends()) check_against_cpu(name, {{"MASQ_VK_MAX_BINDING_BYTES", "4096"}});
}

// 64 instances per TLAS: masq's 600 instances make 10 parts (rtpipeline: 10 launches,
// each looking nearer than the last), cluster's some; 50 primitives per BLAS: ref's
// 200-primitive geometry makes 4 BLAS, the mesh 3.
TEST(LargeScenes, DriverTraversalSplitTlasAndBlasMatchCpu) {
  for (const std::string& name : driver_backends())
    check_against_cpu(name, {{"MASQ_RQ_MAX_INSTANCES", "64"}, {"MASQ_RQ_MAX_PRIMITIVES", "50"}});
}

TEST(LargeScenes, DriverTraversalSplitAndAddressedTogetherMatchCpu) {
  for (const std::string& name : driver_backends())
    check_against_cpu(name, {{"MASQ_RQ_MAX_INSTANCES", "100"},
                             {"MASQ_RQ_MAX_PRIMITIVES", "64"},
                             {"MASQ_VK_MAX_BINDING_BYTES", "4096"}});
}

// The binary-hierarchy tracer (kernels/trace_bv.comp) reads its node and leaf arrays
// the same way: every node type by address gives the cpu tracer's hits.
TEST(LargeScenes, VulkanBvTracerArraysByAddressMatchCpu) {
  std::string why;
  std::unique_ptr<BvTracer> vk =
      masq::test::open_or_fail("vulkan", [](const std::string& n) { return make_bv_tracer(n); }, &why);
  if (!vk) GTEST_SKIP() << why;
  std::unique_ptr<BvTracer> cpu = make_bv_tracer("cpu");
  Scene scene = random_scene(PrimType::Capsule, 9);
  std::vector<Ray> rays = random_rays(8, 1024);
  for (BvType t : {BvType::Aabb, BvType::Sphere, BvType::Obb, BvType::Scb}) {
    SCOPED_TRACE(bv_type_name(t));
    BvOptions o;
    o.type = t;
    BvScene bv = build_bv_scene(scene, o);
    std::vector<Hit> want(rays.size()), got(rays.size());
    cpu->set_scene(bv);
    cpu->trace(rays, want, {});
    ScopedEnv k("MASQ_VK_MAX_BINDING_BYTES", "4096");
    vk->set_scene(bv);
    vk->trace(rays, got, {});
    Diff d = compare(want, got, true);
    EXPECT_GT(d.hits, 100);
    EXPECT_EQ(d.hit_miss + d.wrong_prim + d.wrong_t, 0) << d.first;
  }
}

// Over one allocation there is no way round: a clear error naming the array, its size
// and the limit; and a malformed knob is named too. The backend works afterwards.
TEST(LargeScenes, ArrayOverOneAllocationIsAClearError) {
  PackedScene packed = build_accel(random_scene(PrimType::Capsule, 5), Method::Ref);
  for (const char* name : {"vulkan", "rayquery", "rtpipeline"}) {
    std::unique_ptr<Backend> be = backend_or_fail(name);
    if (!be) continue;
    SCOPED_TRACE(name);
    {
      ScopedEnv k("MASQ_VK_MAX_ALLOCATION_BYTES", "4096"); // e.g. 200 capsules: 6400 bytes
      try {
        be->set_scene(packed);
        ADD_FAILURE() << "no error for an array over the allocation limit";
      } catch (const Error& e) {
        // "<backend>: scene <array> needs <N> bytes in one buffer; the device allows 4096
        // (maxMemoryAllocationSize)", N > 4096.
        std::string what = e.what();
        const std::string head = std::string(name) + ": scene ";
        const std::string tail = " bytes in one buffer; the device allows 4096 (maxMemoryAllocationSize)";
        EXPECT_EQ(what.rfind(head, 0), 0u) << what;
        std::size_t needs = what.find(" needs ");
        std::size_t end = what.find(tail);
        ASSERT_NE(needs, std::string::npos) << what;
        ASSERT_NE(end, std::string::npos) << what;
        EXPECT_EQ(end + tail.size(), what.size()) << what;
        EXPECT_GT(std::stoull(what.substr(needs + 7, end - needs - 7)), 4096u) << what;
      }
    }
    {
      ScopedEnv k("MASQ_VK_MAX_BINDING_BYTES", "12kB");
      try {
        be->set_scene(packed);
        ADD_FAILURE() << "no error for a malformed knob";
      } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("MASQ_VK_MAX_BINDING_BYTES='12kB' is not a positive integer"),
                  std::string::npos)
            << e.what();
      }
    }
    be->set_scene(packed);
    EXPECT_GT(compare(trace(*be, random_rays(3, 512), Query::Closest), trace(*be, random_rays(3, 512), Query::Closest),
                      true)
                  .hits,
              0);
  }
}

// OpenCL has no way round CL_DEVICE_MAX_MEM_ALLOC_SIZE either (no binding limit below
// it): the array is named.
TEST(LargeScenes, OpenClArrayOverOneAllocationIsAClearError) {
  std::string why;
  std::unique_ptr<Backend> be = backend_or_fail("opencl", &why);
  if (!be) GTEST_SKIP() << why;
  PackedScene packed = build_accel(random_scene(PrimType::Capsule, 5), Method::Ref);
  {
    ScopedEnv k("MASQ_CL_MAX_ALLOC_BYTES", "4096");
    try {
      be->set_scene(packed);
      ADD_FAILURE() << "no error for an array over the allocation limit";
    } catch (const Error& e) {
      std::string what = e.what();
      EXPECT_EQ(what.rfind("opencl: scene array '", 0), 0u) << what;
      EXPECT_NE(what.find("bytes, more than the device's largest allocation (CL_DEVICE_MAX_MEM_ALLOC_SIZE = 4096 "
                          "bytes)"),
                std::string::npos)
          << what;
    }
  }
  be->set_scene(packed);
  std::vector<Hit> hits = trace(*be, random_rays(3, 512), Query::Closest);
  EXPECT_TRUE(std::any_of(hits.begin(), hits.end(), [](const Hit& h) { return h.prim >= 0; }));
}

// The ray-query plan on its own: every primitive of a split geometry in exactly one
// BLAS run, in leaf order, each run within the limit; one TLAS entry per (instance, run).
TEST(LargeScenes, RayQueryPlanCutsLeafOrderIntoRuns) {
  Scene scene = random_scene(PrimType::Capsule, 12); // 200 capsules x 3 instances, 128 triangles x 1
  PackedScene s = build_accel(scene, Method::Ref);
  vk::RayQueryPlan plan = vk::plan_ray_query(s, 50);
  ASSERT_EQ(plan.blas.size(), 4u + 3u); // ceil(200/50) + ceil(128/50)
  EXPECT_EQ(plan.entries.size(), 3u * 4u + 1u * 3u);
  std::vector<std::int32_t> map = vk::primitive_id_map(s, plan);
  for (std::size_t g = 0; g < 2; ++g) {
    std::vector<std::int32_t> order = vk::geometry_leaf_order(s, g), joined;
    for (std::size_t b = 0; b < plan.blas.size(); ++b) {
      if (plan.blas[b].geom != int(g)) continue;
      EXPECT_LE(plan.blas[b].count, 50u);
      joined.insert(joined.end(), map.begin() + map[b], map.begin() + map[b] + std::ptrdiff_t(plan.blas[b].count));
    }
    EXPECT_EQ(joined, order) << "geometry " << g;
  }
  // Without a limit below the counts: one BLAS per geometry, one entry per instance.
  vk::RayQueryPlan whole = vk::plan_ray_query(s, (1u << 24) - 1);
  EXPECT_EQ(whole.blas.size(), 2u);
  EXPECT_EQ(whole.entries.size(), s.instances.size());
}

// rtpipeline's shader binding table within the device's limits: a hit record (group
// handle + 16 bytes) over maxShaderGroupStride, or a table over one allocation, is one
// error naming the limit. No driver reports so small a stride: MASQ_RT_MAX_GROUP_STRIDE
// lowers it.
TEST(LargeScenes, BindingTableOverTheDeviceLimitsIsAClearError) {
  std::string why;
  std::shared_ptr<vk::Context> ctx = masq::test::open_or_fail(
      "rtpipeline", [](const std::string& n) { return vk::Context::get(n.c_str(), DeviceNeed::RayPipeline); }, &why);
  if (!ctx) GTEST_SKIP() << why;
  vk::KernelLayout layout(*ctx, vk::kernel_descriptor_types(), sizeof(kernel::TraceParams), vk::kRtShaderStages);
  const PackedScene s = build_accel(random_scene(PrimType::Capsule, 13), Method::Ref);
  const vk::RayQueryPlan plan = vk::plan_ray_query(s, 50, "rtpipeline");
  vk::RtPipeline pipeline(*ctx, layout, kernel_variant(s.features, {false, false}), false, "rtpipeline");
  EXPECT_NO_THROW(vk::BindingTable(*ctx, pipeline, plan, "rtpipeline"));
  auto message = [&] {
    try {
      vk::BindingTable t(*ctx, pipeline, plan, "rtpipeline");
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  std::string stride;
  {
    ScopedEnv no_room("MASQ_RT_MAX_GROUP_STRIDE", std::to_string(ctx->rt_props().shaderGroupHandleSize)); // no room for the record's data
    stride = message();
  }
  EXPECT_EQ(stride.rfind("rtpipeline: a hit record takes ", 0), 0u) << stride;
  EXPECT_NE(stride.find("(maxShaderGroupStride)"), std::string::npos) << stride;
  ScopedEnv small("MASQ_VK_MAX_ALLOCATION_BYTES", "256");
  const std::string bytes = message();
  EXPECT_EQ(bytes.rfind("rtpipeline: the shader binding table of ", 0), 0u) << bytes;
  EXPECT_NE(bytes.find("the device allows 256"), std::string::npos) << bytes;
}
