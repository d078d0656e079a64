// The node formats change how the BVH is stored and tested, never what a ray hits: on
// each backend, random instanced scenes holding every primitive type, built with every
// method, traced in both modes for the closest hit and for occlusion, must give w8 and
// q8 the hits of w4. Closest: the same primitive, geometry and instance, t within 1e-6
// relative (the same intersector on the same ray; only the visiting order differs).
// The binary builder with spatial splits and reinsertion is checked too (ref).
// Any hit: the same occluded/unoccluded answer (which blocker is found first is up to
// the traversal order, so the primitive may differ by design).
#include "bvh/twolevel/build_accel.h"
#include "host/backend.h"
#include "scenes/camera.h"
#include "scenes/generators.h"
#include "tests/random_rays.h"
#include <gtest/gtest.h>
#include <cctype>
#include <cmath>
#include <tuple>
#include <cstdlib>
#include <random>
#include "tests/random_affine.h"
#include "tests/test_env.h"

using namespace masq;
using masq::test::random_rays;
using masq::test::random_affine;

namespace {

constexpr double kRelT = 1e-6;

Scene every_primitive_scene(std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  Scene s;
  s.name = "every primitive " + std::to_string(seed);
  for (PrimType t : {PrimType::Triangle, PrimType::Capsule, PrimType::RoundCone, PrimType::Sphere, PrimType::Curve,
                     PrimType::Ribbon})
    s.geometries.push_back(t == PrimType::Triangle ? make_random_mesh(96, 1.0, seed + 7)
                                                   : make_random_geometry(t, 150, 0.004f, 0.05f, 1.0, seed + int(t)));
  for (std::uint32_t g = 0; g < s.geometries.size(); ++g)
    for (int i = 0; i < 2; ++i) s.instances.push_back({g, random_affine(rng)});
  return s;
}


std::vector<kernel::Hit> trace(Backend& be, const PackedScene& ps, const std::vector<kernel::Ray>& rays, Query q) {
  be.set_scene(ps);
  std::vector<kernel::Hit> hits(rays.size());
  be.trace(rays, hits, {}, q);
  return hits;
}

// One case: a method, a mode and a builder, traced with every node format. Each case is
// its own test (backend x case), so ctest runs them in parallel and none takes minutes on
// lavapipe, where every kernel variant is a pipeline compile (issue 40: the vulkan_bound
// instance of the whole list took 785 s alone).
struct Case {
  Method method;
  Mode mode;
  Builder builder;
};
std::vector<Case> every_case() {
  std::vector<Case> cases;
  for (Method method : {Method::Ref, Method::Masq, Method::Cluster, Method::Auto})
    for (Mode mode : {Mode::Robust, Mode::Fast}) cases.push_back({method, mode, Builder::Sah});
  // Spatial splits put a primitive in several leaves and clip the boxes: the same hits too.
  cases.push_back({Method::Ref, Mode::Robust, Builder::SbvhReinsert});
  return cases;
}

using Param = std::tuple<std::string, int>; // backend (vulkan_bound: descriptor-bound arrays), case index
class NodeFormatsAgree : public ::testing::TestWithParam<Param> {};

// vulkan_bound: the vulkan backend with descriptor-bound scene arrays (the kernels' second
// declaration of the node binding as words) instead of its default buffer addresses.
struct AddressingEnv {
  explicit AddressingEnv(bool bound) : set(bound) {
    if (set) setenv("MASQ_VK_ADDRESSING", "bound", 1);
  }
  ~AddressingEnv() {
    if (set) unsetenv("MASQ_VK_ADDRESSING");
  }
  bool set;
};

TEST_P(NodeFormatsAgree, EveryNodeFormatAndQuery) {
  const std::string& param = std::get<0>(GetParam());
  const std::string backend = param.substr(0, param.find('_'));
  AddressingEnv env(param == "vulkan_bound");
  std::string why;
  std::unique_ptr<Backend> be =
      masq::test::open_or_fail(backend, [](const std::string& n) { return make_backend(n); }, &why);
  if (!be) GTEST_SKIP() << why;
  Scene scene = every_primitive_scene(3);
  std::vector<kernel::Ray> rays = random_rays(4, 2048);
  const Case c = every_case().at(std::size_t(std::get<1>(GetParam())));
  {
    const Method method = c.method;
    const Mode mode = c.mode;
    AccelOptions opt;
    opt.mode = mode;
    opt.builder.kind = c.builder;
    opt.cluster.max_size = 8; // several members per cluster even in this small scene
    std::vector<PackedScene> built;
    for (NodeFormat f : node_format_table.values()) { // w4 first: the baseline
      opt.nodes = f;
      built.push_back(build_accel(scene, method, opt));
    }
    for (Query q : {Query::Closest, Query::Any}) {
      std::vector<kernel::Hit> base = trace(*be, built[0], rays, q);
      int hits = 0;
      for (const kernel::Hit& h : base) hits += h.prim >= 0;
      EXPECT_GT(hits, int(rays.size()) / 20) << "too few hits for the comparison to mean anything";
      for (std::size_t k = 1; k < built.size(); ++k) {
        std::vector<kernel::Hit> got = trace(*be, built[k], rays, q);
        std::string what = std::string(method_name(method)) + " " + builder_name(c.builder) + " " +
                           mode_name(mode) + " " +
                           (q == Query::Any ? "any" : "closest") + " " + node_format_name(built[k].features.nodes);
        int bad = 0;
        for (std::size_t i = 0; i < rays.size(); ++i) {
          const kernel::Hit& a = base[i];
          const kernel::Hit& b = got[i];
          bool same = (a.prim >= 0) == (b.prim >= 0);
          if (same && q == Query::Closest && a.prim >= 0)
            same = a.prim == b.prim && a.geom == b.geom && a.inst == b.inst &&
                   std::abs(a.t - b.t) <= kRelT * std::abs(a.t);
          if (!same && bad++ < 3)
            ADD_FAILURE() << what << ": ray " << i << ": w4 prim " << a.prim << " geom " << a.geom << " inst "
                          << a.inst << " t " << a.t << "; got prim " << b.prim << " geom " << b.geom << " inst "
                          << b.inst << " t " << b.t;
        }
        EXPECT_EQ(bad, 0) << what;
      }
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Backends, NodeFormatsAgree,
                         ::testing::Combine(::testing::Values("cpu", "opencl", "vulkan", "vulkan_bound"),
                                            ::testing::Range(0, int(every_case().size()))),
                         [](const ::testing::TestParamInfo<Param>& i) {
                           const Case c = every_case().at(std::size_t(std::get<1>(i.param)));
                           std::string name = std::get<0>(i.param) + "_" + method_name(c.method) + "_" +
                                              mode_name(c.mode) + "_" + builder_name(c.builder);
                           for (char& ch : name)
                             if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
                           return name;
                         });

} // namespace
