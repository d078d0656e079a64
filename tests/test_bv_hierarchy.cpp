// Binary bounding-volume hierarchies (AABB, ball, OBB, slab cut ball): every stored
// fp32 volume contains its subtree's exact primitive hulls (checked in double); every
// kernel ray/volume test is conservative (rays through points inside never rejected);
// traversal with every volume type on every backend agrees with the long-double oracle
// under the tolerances of tests/test_cross_backend.cpp and never culls a hit that the
// two-level reference traversal finds.
#define MASQ_KERNEL_VARIANT v_bv_test
#include "kernels/bv_tests.h"

#include "bvh/bounds/bounding_sphere.h"
#include "bvh/bv/bv_fit.h"
#include "bvh/bv/bv_scene.h"
#include "bvh/twolevel/build_accel.h"
#include "host/bv_tracer.h"
#include "oracle/oracle.h"
#include "scenes/camera.h"
#include "scenes/generators.h"
#include <gtest/gtest.h>
#include <cmath>
#include <cstdlib>
#include <map>
#include <random>
#include <tuple>
#include "tests/random_affine.h"
#include "tests/test_env.h"

using namespace masq;
using masq::test::random_affine;
namespace kv = masq::kernel::v_bv_test;

namespace {

constexpr BvType kTypes[] = {BvType::Aabb, BvType::Sphere, BvType::Obb, BvType::Scb};


// Every primitive type, thin and dense, plus a mesh; the second instance of the thin
// geometries is rotated and non-uniformly scaled.
Scene mixed_scene(std::uint64_t seed) {
  Scene s;
  s.name = "bv mixed " + std::to_string(seed);
  s.geometries.push_back(make_random_mesh(200, 2.0, seed));
  s.geometries.push_back(make_random_capsules(60, 0.002f, 0.02f, 1.5, seed + 1));
  s.geometries.push_back(make_random_cones(50, 0.002f, 0.03f, 1.5, seed + 2));
  s.geometries.push_back(make_random_spheres(50, 0.005f, 0.05f, 1.5, seed + 3));
  s.geometries.push_back(make_random_curves(30, 0.003f, 0.01f, 1.5, seed + 4));
  std::mt19937_64 rng(seed);
  for (std::uint32_t g = 0; g < 5; ++g) s.instances.push_back({g, {}});
  for (std::uint32_t g = 1; g < 5; ++g) s.instances.push_back({g, random_affine(rng, 1.0, 0.5, 1.0)});
  frame_scene(s);
  return s;
}

// Subtree leaf-entry ranges of a flat hierarchy (child adjacency), by node.
template <class N>
void ranges(const std::vector<N>& nodes, int i, std::vector<std::pair<int, int>>& out) {
  const N& n = nodes[std::size_t(i)];
  if (n.count > 0) {
    out[std::size_t(i)] = {n.child, n.count};
    return;
  }
  ranges(nodes, n.child, out);
  ranges(nodes, n.child + 1, out);
  auto [lf, lc] = out[std::size_t(n.child)];
  auto [rf, rc] = out[std::size_t(n.child + 1)];
  ASSERT_EQ(lf + lc, rf) << "subtree of node " << i << " not contiguous";
  out[std::size_t(i)] = {lf, lc + rc};
}

glm::dvec3 d3(const float* v) { return {v[0], v[1], v[2]}; }

// Largest violation of containment of the ball (c, r) in a node, in double (<= 0: inside).
double excess(const kernel::BvNodeAabb& n, const glm::dvec3& c, double r) {
  double e = -INFINITY;
  for (int k = 0; k < 3; ++k) e = std::max({e, n.lo[k] - (c[k] - r), (c[k] + r) - n.hi[k]});
  return e;
}
double excess(const kernel::BvNodeSphere& n, const glm::dvec3& c, double r) {
  return glm::length(c - d3(n.center)) + r - n.radius;
}
double excess(const kernel::BvNodeObb& n, const glm::dvec3& c, double r) {
  const float* ax[3] = {n.axis0, n.axis1, n.axis2};
  const float hf[3] = {n.half0, n.half1, n.half2};
  double e = -INFINITY;
  for (int k = 0; k < 3; ++k) {
    glm::dvec3 a = d3(ax[k]);
    e = std::max(e, std::abs(glm::dot(a, c - d3(n.center))) + r * glm::length(a) - hf[k]);
  }
  return e;
}
double excess(const kernel::BvNodeScb& n, const glm::dvec3& c, double r) {
  glm::dvec3 a = d3(n.normal), v = c - d3(n.center);
  double s = glm::dot(a, v), rr = r * glm::length(a);
  return std::max({glm::length(v) + r - n.radius, s + rr - n.e, n.f - (s - rr)});
}

template <class N>
void check_containment(const BvScene& bs, const std::vector<N>& nodes) {
  ASSERT_FALSE(nodes.empty());
  WorldPrims wp = world_prims(bs.prims);
  std::map<std::tuple<int, int, int>, std::size_t> index;
  for (std::size_t i = 0; i < wp.refs.size(); ++i) index[{wp.refs[i].geom, wp.refs[i].prim, wp.refs[i].scene_inst}] = i;
  ASSERT_EQ(bs.bv_prims.size(), wp.refs.size()) << "every primitive in exactly one leaf";
  std::vector<std::pair<int, int>> range(nodes.size(), {-1, 0});
  ranges(nodes, 0, range);
  ASSERT_EQ(range[0].second, int(bs.bv_prims.size()));
  int checked = 0;
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    if (range[i].first < 0) continue; // unreachable: counted below
    for (int j = range[i].first; j < range[i].first + range[i].second; ++j) {
      const kernel::BvPrimRef& r = bs.bv_prims[std::size_t(j)];
      const BallHull& h = wp.hulls[index.at({r.geom, r.prim, r.scene_inst})];
      for (int b = 0; b < h.count; ++b) {
        ASSERT_LE(excess(nodes[i], h.centre[b], h.radius[b]), 0.0)
            << bv_type_name(bs.type) << " node " << i << " misses ball " << b << " of prim " << r.prim << " geom "
            << r.geom << " inst " << r.scene_inst;
        ++checked;
      }
    }
  }
  int reachable = 0;
  for (auto& rg : range) reachable += rg.first >= 0;
  EXPECT_EQ(reachable, int(nodes.size())) << "unreachable nodes";
  EXPECT_GT(checked, 0);
}

} // namespace

TEST(BvFit, MinBallIsExactOnSimplex) {
  // Minimum ball of a regular tetrahedron's vertices: its circumsphere, radius sqrt(3/8) * edge.
  std::vector<glm::dvec3> p = {{1, 1, 1}, {1, -1, -1}, {-1, 1, -1}, {-1, -1, 1}, {0, 0, 0}, {0.5, 0.2, -0.1}};
  Ball b = min_ball(p);
  EXPECT_NEAR(b.radius, std::sqrt(3.0), 1e-12);
  EXPECT_NEAR(glm::length(b.centre), 0.0, 1e-12);
  // Two far points and clutter between them: the ball of the pair.
  std::vector<glm::dvec3> q = {{-3, 0, 0}, {3, 0, 0}, {0, 1, 0}, {1, -1, 0.5}, {0, 0, 2}};
  EXPECT_NEAR(min_ball(q).radius, 3.0, 1e-12);
}

TEST(BvFit, ScbAreaMatchesBallAndHalfBall) {
  const double pi = 3.14159265358979323846;
  EXPECT_NEAR(scb_area(2.0, 5.0, -5.0), 4 * pi * 4, 1e-9); // slab wider than the ball
  EXPECT_NEAR(scb_area(2.0, 0.0, -5.0), 2 * pi * 4 + pi * 4, 1e-9); // hemisphere + disc
  EXPECT_NEAR(scb_area(1.0, 0.0, 0.0), 2 * pi, 1e-9);              // a flat disc, both sides
}

TEST(BvFit, EveryNodeContainsItsPrimitives) {
  Scene s = mixed_scene(7);
  for (BvBuilder builder : {BvBuilder::ObbSweep, BvBuilder::BinnedSah})
    for (BvType t : kTypes) {
      SCOPED_TRACE(std::string(bv_type_name(t)) + " " + bv_builder_name(builder));
      BvOptions o;
      o.type = t;
      o.builder = builder;
      BvScene bs = build_bv_scene(s, o);
      EXPECT_GT(bs.stats.depth, 1);
      switch (t) {
        case BvType::Aabb: check_containment(bs, bs.bv_aabb); break;
        case BvType::Sphere: check_containment(bs, bs.bv_sphere); break;
        case BvType::Obb: check_containment(bs, bs.bv_obb); break;
        case BvType::Scb: check_containment(bs, bs.bv_scb); break;
      }
    }
}

TEST(BvFit, ScbSlabChoiceDependsOnP) {
  // p only re-weights the slab choice: the ball and topology stay, some normals change.
  Scene s = mixed_scene(3);
  BvOptions a, b;
  a.scb_p = 0.0;
  b.scb_p = 0.9;
  BvScene x = build_bv_scene(s, a), y = build_bv_scene(s, b);
  ASSERT_EQ(x.bv_scb.size(), y.bv_scb.size());
  int differ = 0;
  for (std::size_t i = 0; i < x.bv_scb.size(); ++i) {
    EXPECT_EQ(x.bv_scb[i].radius, y.bv_scb[i].radius);
    differ += x.bv_scb[i].normal[0] != y.bv_scb[i].normal[0] || x.bv_scb[i].normal[1] != y.bv_scb[i].normal[1];
  }
  EXPECT_GT(differ, 0);
}

// Random volumes, random points inside them (many on the boundary), rays through those
// points from far away: the tests must never answer +inf.
TEST(BvRayTests, ConservativeForPointsInside) {
  std::mt19937_64 rng(42);
  std::uniform_real_distribution<double> u(-1.0, 1.0), u01(0.0, 1.0);
  int tried[4] = {0, 0, 0, 0}, missed[4] = {0, 0, 0, 0};
  for (int iter = 0; iter < 20000; ++iter) {
    double scale = std::pow(10.0, 4.0 * u(rng));                 // 1e-4 .. 1e4
    glm::dvec3 centre = glm::dvec3(u(rng), u(rng), u(rng)) * scale * std::pow(10.0, 2.0 * u01(rng));
    glm::dmat3 axes = glm::dmat3(1.0);
    {
      glm::dvec3 a = glm::normalize(glm::dvec3(u(rng), u(rng), u(rng)));
      glm::dvec3 b = glm::normalize(glm::cross(a, glm::dvec3(u(rng), u(rng), u(rng))));
      axes = glm::dmat3(a, b, glm::cross(a, b));
    }
    glm::dvec3 half = glm::dvec3(0.01 + u01(rng), 0.01 + u01(rng), 0.01 + u01(rng)) * scale;
    double radius = glm::length(half) * (0.6 + 0.4 * u01(rng));
    // A candidate point, pushed onto the boundary half of the time.
    glm::dvec3 local(u(rng), u(rng), u(rng));
    if (iter % 2) local[iter % 3] = local[iter % 3] > 0 ? 1.0 : -1.0;
    glm::dvec3 x = centre + axes * (local * half);
    glm::dvec3 dir(u(rng), u(rng), u(rng));
    if (iter % 7 == 0) dir[iter % 3] = 0.0; // parallel to a slab
    if (glm::length(dir) == 0) continue;
    double tx = std::pow(10.0, 3.0 * u01(rng));
    glm::vec3 d = glm::vec3(dir * scale * std::pow(10.0, u(rng)) / glm::length(dir));
    glm::vec3 o = glm::vec3(x - tx * glm::dvec3(d));
    glm::dvec3 xp = glm::dvec3(o) + tx * glm::dvec3(d); // the point the fp32 ray really passes
    kv::BvRay ray = kv::bv_ray(o, d);
    float tmax = std::nextafter(float(tx), INFINITY);
    // Nodes, fp32 as stored; each checked for xp in double before asking the kernel.
    kernel::BvNodeAabb na{};
    for (int k = 0; k < 3; ++k) {
      double lo = INFINITY, hi = -INFINITY;
      for (int c = 0; c < 8; ++c) {
        glm::dvec3 cl((c & 1 ? 1 : -1) * half.x, (c & 2 ? 1 : -1) * half.y, (c & 4 ? 1 : -1) * half.z);
        double v = (centre + axes * cl)[k];
        lo = std::min(lo, v), hi = std::max(hi, v);
      }
      na.lo[k] = round_down(lo);
      na.hi[k] = round_up(hi);
    }
    kernel::BvNodeSphere ns{};
    for (int k = 0; k < 3; ++k) ns.center[k] = float(centre[k]);
    ns.radius = float(radius);
    kernel::BvNodeObb nb{};
    float* ax[3] = {nb.axis0, nb.axis1, nb.axis2};
    float* hf[3] = {&nb.half0, &nb.half1, &nb.half2};
    for (int k = 0; k < 3; ++k) {
      for (int j = 0; j < 3; ++j) ax[k][j] = float(axes[k][j]);
      *hf[k] = float(half[k]);
      nb.center[k] = float(centre[k]);
    }
    kernel::BvNodeScb nc{};
    for (int k = 0; k < 3; ++k) nc.center[k] = ns.center[k], nc.normal[k] = nb.axis0[k];
    nc.radius = ns.radius;
    nc.e = float(half.x * 0.7);
    nc.f = float(-half.x * (0.3 + 0.6 * u01(rng)));
    bool inside[4] = {excess(na, xp, 0) <= 0, excess(ns, xp, 0) <= 0, excess(nb, xp, 0) <= 0, excess(nc, xp, 0) <= 0};
    float got[4] = {kv::bv_hit_aabb(na, ray, 0.0f, tmax), kv::bv_hit_sphere(ns, ray, 0.0f, tmax),
                    kv::bv_hit_obb(nb, ray, 0.0f, tmax), kv::bv_hit_scb(nc, ray, 0.0f, tmax)};
    for (int k = 0; k < 4; ++k) {
      if (!inside[k]) continue;
      ++tried[k];
      if (got[k] == INFINITY) ++missed[k];
      else EXPECT_LE(got[k], tmax) << "entry bound beyond the point inside";
    }
  }
  for (int k = 0; k < 4; ++k) {
    SCOPED_TRACE(bv_type_name(kTypes[k]));
    EXPECT_GT(tried[k], 3000);
    EXPECT_EQ(missed[k], 0) << "false misses";
  }
}

namespace {

std::unique_ptr<BvTracer> tracer_or_fail(const std::string& name) {
  return masq::test::open_or_fail(name, [](const std::string& n) { return make_bv_tracer(n); });
}

} // namespace

// Same tolerances as tests/test_cross_backend.cpp (see there for why).
TEST(BvTraversal, AgreesWithOracleOnEveryBackend) {
  Scene s = mixed_scene(11);
  std::vector<kernel::Ray> rays = make_camera_rays(s.camera, 48, 40);
  oracle::Oracle oracle(s, {.exact_clearance_below = 1}); // clearance read below 1e-3 only
  std::vector<oracle::OracleHit> truth = oracle.trace_all(rays);
  // The two-level reference traversal (cpu) with the same intersectors: a hierarchy
  // that culls conservatively can only find the same or a nearer hit.
  std::unique_ptr<Backend> cpu = make_backend("cpu");
  cpu->set_scene(build_accel(s, Method::Ref));
  std::vector<kernel::Hit> ref(rays.size());
  cpu->trace(rays, ref, {});
  for (const std::string& name : bv_backend_names()) {
    std::unique_ptr<BvTracer> tr = tracer_or_fail(name);
    if (!tr) continue;
    for (BvType t : kTypes) {
      SCOPED_TRACE(name + " " + bv_type_name(t));
      BvOptions o;
      o.type = t;
      tr->set_scene(build_bv_scene(s, o));
      std::vector<kernel::Hit> hits(rays.size());
      std::vector<kernel::RayStats> stats(rays.size());
      tr->trace(rays, hits, stats);
      int compared = 0, wrong = 0, culled = 0, tests = 0;
      std::string first;
      for (std::size_t i = 0; i < rays.size(); ++i) {
        tests += stats[i].blas_nodes;
        if (ref[i].prim >= 0 && !(hits[i].prim >= 0 && hits[i].t <= ref[i].t * (1.0f + 1e-6f))) ++culled;
        const oracle::OracleHit& h = truth[i];
        if (h.clearance < 1e-3L) continue;
        ++compared;
        bool ok = (h.prim >= 0) == (hits[i].prim >= 0);
        if (ok && h.prim >= 0) {
          bool separated = (h.second_t - h.t) > 1e-4L * h.t;
          ok = std::abs(double(h.t) - hits[i].t) <= 1e-4 * double(h.t) &&
               (!separated || (h.prim == hits[i].prim && h.geom == hits[i].geom && h.inst == hits[i].inst));
        }
        if (!ok && wrong++ == 0)
          first = "ray " + std::to_string(i) + ": oracle prim " + std::to_string(h.prim) + " t " +
                  std::to_string(double(h.t)) + ", got prim " + std::to_string(hits[i].prim) + " t " +
                  std::to_string(hits[i].t);
      }
      EXPECT_GT(compared, int(rays.size() * 7 / 8));
      EXPECT_EQ(wrong, 0) << first;
      EXPECT_EQ(culled, 0) << "hits of the two-level traversal lost";
      // The counters ran: at least the root test per valid ray.
      EXPECT_GE(tests, int(rays.size()));
      // Plain variant: same hits.
      std::vector<kernel::Hit> plain(rays.size());
      tr->trace(rays, plain, {});
      for (std::size_t i = 0; i < rays.size(); ++i) ASSERT_EQ(plain[i].prim, hits[i].prim) << "ray " << i;
    }
  }
}
