// One contraction policy on every backend (docs/robustness.md, "Float semantics"): in
// robust mode the compute backends run the same fp32 operations in the same order, so
// opencl and vulkan must return the cpu's hits BIT FOR BIT (t, normal, u, v, primitive,
// instance) and its per-ray counters, for every primitive type and every method. Before
// the policy held everywhere, opencl (OpenCL C's FP_CONTRACT defaults to ON: PoCL fused
// multiply-adds the others round twice) differed in t on 12-59% of these hits, and
// vulkan (lavapipe splits fma() into a product and a sum, losing the curve's exact
// products) on a quarter of the curve hits.
//
// rayquery: the driver finds the candidates and, for a scene instance's own BLAS (every
// ref candidate, and triangles in every method), moves the ray into the instance with
// its own fp32 arithmetic (the object ray the shader reads), whose roundings no kernel
// controls. Masquerade and cluster candidates get the kernel's own transform
// (kernels/rayquery.comp), so there rayquery must match the cpu bit for bit too; hits
// through the driver's object ray must agree on the primitive and on t within
// kDriverRayRelT (below). Its per-ray counters are the driver's (-1): not compared.
#include "bvh/twolevel/build_accel.h"
#include "host/backend.h"
#include "scenes/camera.h"
#include "scenes/generators.h"
#include "tests/random_affine.h"
#include "tests/test_env.h"
#include <gtest/gtest.h>
#include <bit>
#include <cmath>
#include <cstdio>
#include <random>
#include <set>
#include <utility>

using namespace masq;

namespace {

// rayquery, hits through the driver's object ray (see the top): that ray is off by a few
// ulps of |o| and |d| from the kernel's; t moves by that over the sine of the angle of
// incidence at a triangle, and by up to sqrt(2 r delta) at a round silhouette of radius
// r. Measured here: at most 1.5e-4 t (spheres of radius up to 0.05 seen from 2 to 5
// away); 1e-3 leaves a margin. Hit/miss and primitive may flip where a ray passes within
// those ulps of an edge or a silhouette: at most one in a thousand hits.
constexpr double kDriverRayRelT = 1e-3;

// Rays aimed at the primitives of the scene's instances (a random point of a random
// primitive, jittered by about a radius, so that many rays hit and many graze), from
// random directions: most of them reach an intersector, where a contraction shows.
std::vector<kernel::Ray> rays_at_primitives(const Scene& s, int n, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0), u01(0.0, 1.0);
  std::vector<kernel::Ray> rays;
  while (int(rays.size()) < n) {
    const Instance& in = s.instances[std::size_t(rng() % s.instances.size())];
    const Geometry& g = s.geometries[in.geometry];
    const std::size_t k = std::size_t(rng() % g.primitive_count());
    const double w = u01(rng);
    glm::dvec3 p;
    double r = 0.0;
    switch (g.type) {
      case PrimType::Triangle: {
        const glm::uvec3 t = g.triangles[k];
        p = (glm::dvec3(g.vertices[t.x]) + glm::dvec3(g.vertices[t.y]) + glm::dvec3(g.vertices[t.z])) / 3.0;
        break;
      }
      case PrimType::Capsule:
        p = glm::mix(glm::dvec3(g.capsules[k].a), glm::dvec3(g.capsules[k].b), w), r = g.capsules[k].radius;
        break;
      case PrimType::RoundCone:
        p = glm::mix(glm::dvec3(g.round_cones[k].a), glm::dvec3(g.round_cones[k].b), w), r = g.round_cones[k].ra;
        break;
      case PrimType::Sphere: p = glm::dvec3(g.spheres[k].center), r = g.spheres[k].radius; break;
      case PrimType::Ribbon:
        p = glm::mix(glm::dvec3(g.ribbons[k].p0), glm::dvec3(g.ribbons[k].p1), w), r = g.ribbons[k].r0;
        break;
      case PrimType::Curve: {
        const auto& c = g.curves[k].p;
        const double v = 1.0 - w; // Bernstein weights of the cubic at w
        p = v * v * v * glm::dvec3(c[0]) + 3.0 * v * v * w * glm::dvec3(c[1]) + 3.0 * v * w * w * glm::dvec3(c[2]) +
            w * w * w * glm::dvec3(c[3]);
        r = g.curves[k].radius;
        break;
      }
    }
    p += 1.5 * r * glm::dvec3(u(rng), u(rng), u(rng));
    const glm::dvec3 to = in.object_to_world.apply_point(p);
    const glm::dvec3 from = to + glm::normalize(glm::dvec3(u(rng), u(rng), u(rng))) * (2.0 + 3.0 * u01(rng));
    const double scale = 0.3 + 2.0 * u01(rng); // non-unit directions
    rays.push_back(make_ray(from, (to - from) * (scale / glm::length(to - from))));
  }
  return rays;
}

struct Diff {
  int hits = 0;           // rays the cpu hits
  int hit_miss = 0;       // one hits, the other misses
  int prim = 0;           // both hit, another primitive, geometry or instance
  int t_bits = 0;         // same primitive, t differs in its bits
  int surface_bits = 0;   // same primitive and t, normal, u or v differ in their bits
  int t_beyond_bound = 0; // same primitive, |dt| > kDriverRayRelT t
  int counters = 0;       // per-ray counters differ
  double max_rel_t = 0.0;
  std::string first;
};

bool same_bits(float a, float b) { return std::bit_cast<std::uint32_t>(a) == std::bit_cast<std::uint32_t>(b); }

// Rays sorted into two tallies: `exact` where the backend must give the cpu's bits, and
// `driver` where rayquery's driver moved the ray (driver_ray(hit), for either side's hit).
struct Tallies {
  Diff exact, driver;
};

template <class DriverRay>
Tallies compare_bits(const std::vector<kernel::Hit>& want, const std::vector<kernel::Hit>& got,
                     const std::vector<kernel::RayStats>& want_st, const std::vector<kernel::RayStats>& got_st,
                     DriverRay driver_ray) {
  Tallies out;
  for (std::size_t i = 0; i < want.size(); ++i) {
    const kernel::Hit& a = want[i];
    const kernel::Hit& b = got[i];
    Diff& d = (a.prim >= 0 && driver_ray(a)) || (b.prim >= 0 && driver_ray(b)) ? out.driver : out.exact;
    auto note = [&](int& counter, const char* what) {
      ++counter;
      if (d.first.empty()) {
        char buf[256];
        std::snprintf(buf, sizeof buf, "ray %zu: %s (cpu prim %d inst %d t %.9g; got prim %d inst %d t %.9g)", i, what,
                      a.prim, a.inst, a.t, b.prim, b.inst, b.t);
        d.first = buf;
      }
    };
    if (!got_st.empty()) {
      const kernel::RayStats &x = want_st[i], &y = got_st[i];
      if (x.tlas_nodes != y.tlas_nodes || x.blas_nodes != y.blas_nodes || x.transforms != y.transforms ||
          x.isect_calls != y.isect_calls)
        note(d.counters, "counters differ");
    }
    if (a.prim >= 0) ++d.hits;
    if ((a.prim >= 0) != (b.prim >= 0)) {
      note(d.hit_miss, "hit/miss differs");
      continue;
    }
    if (a.prim < 0) continue;
    if (a.prim != b.prim || a.geom != b.geom || a.inst != b.inst) {
      note(d.prim, "different primitive");
      continue;
    }
    const double rel = std::abs(double(a.t) - double(b.t)) / std::abs(double(a.t));
    d.max_rel_t = std::max(d.max_rel_t, rel);
    if (rel > kDriverRayRelT) note(d.t_beyond_bound, "t beyond the bound");
    if (!same_bits(a.t, b.t)) {
      note(d.t_bits, "t differs in its bits");
      continue;
    }
    if (!same_bits(a.normal[0], b.normal[0]) || !same_bits(a.normal[1], b.normal[1]) ||
        !same_bits(a.normal[2], b.normal[2]) || !same_bits(a.u, b.u) || !same_bits(a.v, b.v))
      note(d.surface_bits, "normal, u or v differs in its bits");
  }
  return out;
}

void print(const char* backend, Method m, const char* what, const Scene& s, const Diff& d) {
  std::printf("[ %-8s %-7s %-6s ] %-18s %5d hits: %d hit/miss, %d primitive, %d t bits, %d surface bits, "
              "%d counters; max |dt|/t %.3g\n",
              backend, method_name(m), what, s.name.c_str(), d.hits, d.hit_miss, d.prim, d.t_bits, d.surface_bits,
              d.counters, d.max_rel_t);
}

Scene instanced_scene(PrimType type) {
  std::mt19937_64 rng(51 + int(type));
  Scene s;
  s.name = std::string("instanced ") + prim_type_key(type);
  if (type == PrimType::Triangle) {
    s.geometries.push_back(make_random_mesh(256, 1.0, 61));
  } else {
    s.geometries.push_back(make_random_geometry(type, 200, 0.004f, 0.05f, 1.0, 71 + int(type)));
    s.geometries.push_back(make_random_mesh(128, 1.0, 81));
  }
  for (int i = 0; i < 3; ++i) s.instances.push_back({0, test::random_affine(rng)});
  if (type != PrimType::Triangle) s.instances.push_back({1, test::random_affine(rng)});
  return s;
}

// Every backend against the cpu's bits on a scene of one primitive type, traced with the
// given curve intersector.
void expect_cpu_bits(PrimType type, CurveIsect isect) {
  const Scene s = instanced_scene(type);
  const std::vector<kernel::Ray> rays = rays_at_primitives(s, 6000, 7 + int(type));
  std::unique_ptr<Backend> cpu = make_backend("cpu");
  std::vector<std::unique_ptr<Backend>> others;
  for (const std::string& name : backend_names())
    if (name != "cpu")
      if (std::unique_ptr<Backend> be = test::open_or_fail(name, [](const std::string& n) { return make_backend(n); }))
        others.push_back(std::move(be));
  for (Method m : {Method::Ref, Method::Masq, Method::Cluster}) {
    AccelOptions opt;
    opt.mode = Mode::Robust;
    opt.curve_isect = isect;
    const PackedScene ps = build_accel(s, m, opt);
    cpu->set_scene(ps);
    std::vector<kernel::Hit> want(rays.size());
    std::vector<kernel::RayStats> want_st(rays.size());
    cpu->trace(rays, want, want_st);
    std::set<std::pair<int, int>> driver_placed; // (geometry, scene instance) with a BLAS entry
    for (const kernel::Instance& in : ps.instances)
      if (in.blas_root >= 0 && in.prim != MASQ_INST_CLUSTER) driver_placed.insert({in.geom, in.scene_inst});
    for (const std::unique_ptr<Backend>& be : others) {
      SCOPED_TRACE(be->name() + " " + method_name(m) + " on " + s.name + " (curves: " + curve_isect_name(isect) + ")");
      be->set_scene(ps);
      std::vector<kernel::Hit> got(rays.size());
      // The driver-traversal backends (rayquery, rtpipeline) report no node or transform
      // counters (-1): their hits only.
      const bool rayquery = driver_traversal(be->name());
      std::vector<kernel::RayStats> got_st(rayquery ? 0 : rays.size());
      be->trace(rays, got, got_st);
      // rayquery, rtpipeline: a hit on a (geometry, scene instance) placed as its own BLAS (every ref
      // instance, triangles in every method, and whatever a method keeps in a BLAS) came
      // through the driver's object ray; masquerade and cluster entries did not.
      const Tallies t = compare_bits(want, got, want_st, got_st, [&](const kernel::Hit& h) {
        return rayquery && driver_placed.count({h.geom, h.inst}) != 0;
      });
      print(be->name().c_str(), m, "exact", s, t.exact);
      if (rayquery) print(be->name().c_str(), m, "driver", s, t.driver);
      EXPECT_GT(t.exact.hits + t.driver.hits, int(rays.size() / 2)) << "too few hits to show a contraction";
      EXPECT_EQ(t.exact.hit_miss, 0) << t.exact.first;
      EXPECT_EQ(t.exact.prim, 0) << t.exact.first;
      EXPECT_EQ(t.exact.counters, 0) << t.exact.first;
      EXPECT_EQ(t.exact.t_bits, 0) << t.exact.first;
      EXPECT_EQ(t.exact.surface_bits, 0) << t.exact.first;
      EXPECT_LE(t.driver.hit_miss + t.driver.prim, t.driver.hits / 1000) << t.driver.first;
      EXPECT_EQ(t.driver.t_beyond_bound, 0) << t.driver.first;
    }
  }
}

class CrossBackendBits : public ::testing::TestWithParam<PrimType> {};

TEST_P(CrossBackendBits, RobustHitsEqualTheCpusBits) { expect_cpu_bits(GetParam(), CurveIsect::Phantom); }

// The second curve intersector (kernels/curve_roving.h) on the same curves and rays.
TEST(CrossBackendBitsRoving, RobustCurveHitsEqualTheCpusBits) { expect_cpu_bits(PrimType::Curve, CurveIsect::Roving); }

// The intersector switch reaches every backend's kernel: on each backend, roving's hits
// are phantom's up to rounding (the same surface), yet some differ in their last bits
// (two different searches), which a switch that never left the host could not give.
TEST(CrossBackendBitsRoving, EachBackendRunsTheChosenCurveIntersector) {
  const Scene s = instanced_scene(PrimType::Curve);
  const std::vector<kernel::Ray> rays = rays_at_primitives(s, 6000, 7 + int(PrimType::Curve));
  AccelOptions po, ro;
  ro.curve_isect = CurveIsect::Roving;
  const PackedScene phantom = build_accel(s, Method::Masq, po), roving = build_accel(s, Method::Masq, ro);
  for (const std::string& name : backend_names()) {
    std::unique_ptr<Backend> be = test::open_or_fail(name, [](const std::string& n) { return make_backend(n); });
    if (!be) continue;
    SCOPED_TRACE(name);
    std::vector<kernel::Hit> a(rays.size()), b(rays.size());
    be->set_scene(phantom);
    be->trace(rays, a, {});
    be->set_scene(roving);
    be->trace(rays, b, {});
    int hits = 0, hit_miss = 0, t_bits = 0;
    double max_rel = 0;
    for (std::size_t i = 0; i < rays.size(); ++i) {
      if ((a[i].prim >= 0) != (b[i].prim >= 0)) hit_miss++;
      if (a[i].prim < 0 || b[i].prim < 0) continue;
      hits++;
      t_bits += !same_bits(a[i].t, b[i].t);
      max_rel = std::max(max_rel, std::fabs(double(a[i].t) - double(b[i].t)) / double(a[i].t));
    }
    std::printf("[ %-8s ] phantom vs roving: %d hits, %d hit/miss, %d differ in t's bits, max |dt|/t %.3g\n",
                name.c_str(), hits, hit_miss, t_bits, max_rel);
    EXPECT_GT(hits, int(rays.size() / 2));
    EXPECT_LE(hit_miss, hits / 1000);
    EXPECT_GT(t_bits, 0) << "roving gave phantom's bits on every hit: was it run?";
    EXPECT_LT(max_rel, 1e-3);
  }
}

INSTANTIATE_TEST_SUITE_P(Types, CrossBackendBits,
                         ::testing::Values(PrimType::Triangle, PrimType::Capsule, PrimType::RoundCone, PrimType::Sphere,
                                           PrimType::Curve, PrimType::Ribbon),
                         [](const ::testing::TestParamInfo<PrimType>& i) { return std::string(prim_type_key(i.param)); });

} // namespace
