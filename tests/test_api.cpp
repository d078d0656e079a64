// The public API (include/masq/) on its own: only masq/*.h is included, the test links
// masq::masq alone. Scenes from arrays and files, both methods, every backend, errors,
// and two contexts on two threads at once.
#include "masq/masq.h"
#include <gtest/gtest.h>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <string>
#include <thread>
#include "tests/test_env.h"

using namespace masq::api;

namespace {

bool allow_missing() { return masq::test::missing_backends_allowed(); }

// A context on `name`, or nullptr where the backend is missing (the cause in *why): a
// failure, unless that is allowed. A test of that backend alone then skips with the
// cause; setup installs every backend.
std::unique_ptr<Context> open(const std::string& name, std::string* why = nullptr) {
  try {
    return std::make_unique<Context>(name);
  } catch (const masq::BackendUnavailable& e) {
    if (why != nullptr) *why = std::string(e.what()) + " (MASQ_ALLOW_MISSING_BACKENDS=1)";
    if (!allow_missing()) ADD_FAILURE() << e.what();
    return nullptr;
  }
}

// Rays along +z from z = -5 on a 32 x 32 grid over [-1, 1]^2.
std::vector<Ray> grid_rays(int n = 32) {
  std::vector<Ray> rays;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      Ray r;
      r.org = {-1.0f + 2.0f * (i + 0.5f) / n, -1.0f + 2.0f * (j + 0.5f) / n, -5.0f};
      r.dir = {0, 0, 1};
      rays.push_back(r);
    }
  return rays;
}

// One capsule along x at y = 0 of radius 0.1, one round cone, one sphere at (0.5,0.5,0)
// and two triangles at z = 2 behind everything.
Scene mixed_scene() {
  Scene s;
  Capsule c{{-0.8f, 0, 0}, {0.8f, 0, 0}, 0.1f};
  s.add_capsules({&c, 1});
  RoundCone rc{{-0.5f, -0.6f, 0}, 0.05f, {-0.5f, -0.9f, 0}, 0.02f};
  s.add_round_cones({&rc, 1});
  Sphere sp{{0.5f, 0.5f, 0}, 0.2f};
  s.add_spheres({&sp, 1});
  Curve cu{{{{0.2f, -0.5f, 0}, {0.4f, -0.3f, 0}, {0.6f, -0.7f, 0}, {0.8f, -0.5f, 0}}}, 0.03f};
  s.add_curves({&cu, 1});
  Vec3 v[] = {{-2, -2, 2}, {2, -2, 2}, {2, 2, 2}, {-2, 2, 2}};
  std::uint32_t idx[] = {0, 1, 2, 0, 2, 3};
  s.add_triangles(v, idx);
  return s;
}

int count_geometry(const std::vector<Hit>& hits, int g) {
  int n = 0;
  for (const Hit& h : hits) n += h.geometry == g;
  return n;
}

} // namespace

// What `f` throws as masq::Error, or "(no error)".
template <class F>
std::string message(F&& f) {
  try {
    f();
  } catch (const masq::Error& e) {
    return std::string(e.what());
  }
  return std::string("(no error)");
}

TEST(Api, EveryBackendAndMethodAgreeOnAMixedScene) {
  Scene scene = mixed_scene();
  std::vector<Ray> rays = grid_rays();
  std::vector<Hit> reference;
  for (Method m : {Method::Ref, Method::Masq}) {
    Accel accel = Accel::build(scene, {m, Mode::Robust});
    EXPECT_EQ(accel.stats().instances, 5u); // ref: 5 scene instances; masq: 4 thin prims + the triangle BLAS
    for (const std::string& b : Context::backends()) {
      auto ctx = open(b);
      if (!ctx) continue;
      SCOPED_TRACE(b + " " + (m == Method::Ref ? "ref" : "masq"));
      std::vector<Hit> hits = ctx->trace(accel, rays);
      // Every ray ends on the triangles at worst. The capsule (|x| < 0.8, radius 0.1)
      // covers the rows y = +-1/32 and +-3/32 over 26 columns (|x| <= 0.78125); the
      // round caps add the columns x = +-0.84375 on the two rows y = +-1/32
      // (distance 0.054 from the end points), so 4 * 26 + 2 * 2 hits.
      for (const Hit& h : hits) ASSERT_TRUE(h.hit());
      EXPECT_EQ(count_geometry(hits, 0), 4 * 26 + 4);
      EXPECT_GT(count_geometry(hits, 1), 0);
      EXPECT_GT(count_geometry(hits, 2), 0);
      EXPECT_GT(count_geometry(hits, 3), 0);
      if (reference.empty()) {
        reference = hits;
        continue;
      }
      for (std::size_t i = 0; i < hits.size(); ++i) {
        ASSERT_EQ(hits[i].geometry, reference[i].geometry) << "ray " << i;
        ASSERT_NEAR(hits[i].t, reference[i].t, 1e-4f) << "ray " << i;
      }
    }
  }
}

TEST(Api, NodeFormatsGiveTheSameHitsInFewerBytes) {
  Scene scene = mixed_scene();
  std::vector<Ray> rays = grid_rays();
  Context ctx("cpu");
  Accel w4 = Accel::build(scene, {.method = Method::Masq, .mode = Mode::Robust, .nodes = NodeFormat::W4});
  std::vector<Hit> expected = ctx.trace(w4, rays);
  for (NodeFormat f : node_format_table.values()) {
    Accel a = Accel::build(scene, {.method = Method::Masq, .mode = Mode::Robust, .nodes = f});
    EXPECT_EQ(a.options().nodes, f);
    std::vector<Hit> hits = ctx.trace(a, rays);
    for (std::size_t i = 0; i < hits.size(); ++i) {
      EXPECT_EQ(hits[i].prim, expected[i].prim) << i;
      EXPECT_EQ(hits[i].geometry, expected[i].geometry) << i;
      EXPECT_EQ(hits[i].instance, expected[i].instance) << i;
      EXPECT_FLOAT_EQ(hits[i].t, expected[i].t) << i;
    }
    if (f == NodeFormat::Q8) {
      EXPECT_LT(a.stats().node_bytes, w4.stats().node_bytes);
    }
  }
}

// Every builder reaches the build through the API and traces the same hits (ties at a
// joint aside); sah4's full four-capsule leaves take fewer BLAS nodes than sah's on a
// strand of many segments, sah-priced's one-capsule leaves more.
TEST(Api, BuildersGiveTheSameHits) {
  Scene scene;
  std::vector<Capsule> strand;
  for (int i = 0; i < 400; ++i) {
    float a = 0.05f * float(i), b = 0.05f * float(i + 1);
    strand.push_back({{std::cos(a) * 0.8f, -1.0f + a / 10.0f, std::sin(a) * 0.8f},
                      {std::cos(b) * 0.8f, -1.0f + b / 10.0f, std::sin(b) * 0.8f},
                      0.02f});
  }
  scene.add_capsules(strand);
  std::vector<Ray> rays = grid_rays(48);
  Context ctx("cpu");
  Accel sah = Accel::build(scene, {.method = Method::Ref, .mode = Mode::Robust, .builder = Builder::Sah});
  std::vector<Hit> expected = ctx.trace(sah, rays);
  int hits_seen = 0;
  for (const Hit& h : expected) hits_seen += h.hit();
  EXPECT_GT(hits_seen, 50);
  for (Builder b : {Builder::Sbvh, Builder::SahReinsert, Builder::SbvhReinsert, Builder::Sah4, Builder::SahPriced}) {
    Accel a = Accel::build(scene, {.method = Method::Ref, .mode = Mode::Robust, .builder = b});
    std::vector<Hit> hits = ctx.trace(a, rays);
    for (std::size_t i = 0; i < hits.size(); ++i) {
      ASSERT_FLOAT_EQ(hits[i].t, expected[i].t) << "builder " << int(b) << " ray " << i;
      // Where two segments meet, either may be the closest at the same t (a tie the
      // traversal order decides).
      ASSERT_LE(std::abs(hits[i].prim - expected[i].prim), 1) << "builder " << int(b) << " ray " << i;
    }
    if (b == Builder::Sah4) {
      EXPECT_LT(a.stats().blas_nodes, sah.stats().blas_nodes);
    }
    if (b == Builder::SahPriced) {
      EXPECT_GT(a.stats().blas_nodes, sah.stats().blas_nodes);
    }
  }
}

TEST(Api, InstancesTransformsStatsAndOcclusion) {
  Scene s;
  Sphere sp{{0, 0, 0}, 0.25f};
  std::uint32_t g = s.add_spheres({&sp, 1});
  s.add_instance(g, Transform::translation(-0.5, 0, 0));
  s.add_instance(g, Transform::translation(0.5, 0, 0));
  EXPECT_EQ(s.instance_count(), 2u);
  Accel accel = Accel::build(s);
  Context ctx("cpu");
  Ray rays[3];
  rays[0].org = {-0.5f, 0, -5};
  rays[1].org = {0.5f, 0, -5};
  rays[2].org = {0, 0, -5};
  std::vector<Hit> hits(3);
  std::vector<RayStats> stats(3);
  ctx.trace(accel, rays, hits, stats);
  EXPECT_EQ(hits[0].instance, 0);
  EXPECT_EQ(hits[1].instance, 1);
  EXPECT_FALSE(hits[2].hit());
  EXPECT_NEAR(hits[0].t, 4.75f, 1e-5f);
  EXPECT_NEAR(hits[0].normal.z, -1.0f, 1e-5f);
  EXPECT_GT(stats[0].isect_calls, 0);
  // Occlusion honours tmax: the sphere at t = 4.75 is beyond tmax = 4.
  rays[0].tmax = 4.0f;
  std::uint8_t occ[3];
  ctx.occluded(accel, rays, occ);
  EXPECT_EQ(occ[0], 0);
  EXPECT_EQ(occ[1], 1);
  EXPECT_EQ(occ[2], 0);
}

TEST(Api, LoadsFilesAndFramesACamera) {
  std::string path = ::testing::TempDir() + "masq_api_test.obj";
  {
    std::ofstream f(path);
    f << "v -1 -1 0\nv 1 -1 0\nv 0 1 0\nf 1 2 3\n";
  }
  Scene s = Scene::load(path);
  EXPECT_EQ(s.primitive_count(), 1u);
  std::vector<Ray> rays = s.camera_rays(16, 16);
  ASSERT_EQ(rays.size(), 256u);
  Context ctx("cpu");
  std::vector<Hit> hits = ctx.trace(Accel::build(s, {Method::Ref}), rays);
  int n = 0;
  for (const Hit& h : hits) n += h.hit();
  EXPECT_GT(n, 20); // the framed triangle covers a good part of the view
  std::remove(path.c_str());
  EXPECT_THROW(Scene::load("/nonexistent/x.obj"), masq::Error);
  EXPECT_THROW(Scene::load("scene.unknown"), masq::Error);
}

TEST(Api, BadInputAndMisuseThrowErrorsNamingTheCause) {
  Scene s;
  Vec3 v[] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  std::uint32_t bad[] = {0, 1, 7};
  s.add_triangles(v, bad);
  EXPECT_NE(message([&] { Accel::build(s); }).find("geometry 0 triangle 0"), std::string::npos);
  std::uint32_t two[] = {0, 1};
  EXPECT_NE(message([&] { s.add_triangles(v, two); }).find("multiple of 3"), std::string::npos);
  EXPECT_NE(message([&] { s.add_instance(5); }).find("geometry 5"), std::string::npos);
  EXPECT_NE(message([] { Accel::build(Scene{}); }), "(no error)");
  Capsule nan{{0, 0, 0}, {std::nanf(""), 0, 0}, 0.1f};
  Scene sn;
  sn.add_capsules({&nan, 1});
  EXPECT_NE(message([&] { sn.validate(); }), "(no error)");
  EXPECT_NE(message([] { Context("nonsense"); }).find("nonsense"), std::string::npos);

  Scene ok;
  Sphere sp{{0, 0, 0}, 1};
  ok.add_spheres({&sp, 1});
  Accel accel = Accel::build(ok);
  Context ctx("cpu");
  std::vector<Ray> rays(4);
  std::vector<Hit> hits(3);
  EXPECT_NE(message([&] { ctx.trace(accel, rays, hits); }).find("4 rays"), std::string::npos);
  EXPECT_NE(message([&] { ctx.trace(Accel{}, rays); }).find("not built"), std::string::npos);
}

// Read-back of geometry (with the strands of chained segments), world bounds of placed
// instances, the scene's camera and rays of a given camera, and what auto kept.
TEST(Api, GeometryBoundsCamerasAndTheKeptMethod) {
  Scene s;
  // Two strands: 0-1-2 chained (each segment starts where the last ended), then 3 alone.
  Capsule caps[] = {{{0, 0, 0}, {1, 0, 0}, 0.1f}, {{1, 0, 0}, {2, 0, 0}, 0.1f}, {{5, 0, 0}, {6, 0, 0}, 0.2f}};
  const std::uint32_t g = s.add_capsules(caps);
  Sphere sp{{0, 3, 0}, 0.5f};
  s.add_spheres({&sp, 1});
  GeometryData d = s.geometry(g);
  EXPECT_EQ(d.type, "capsule");
  ASSERT_EQ(d.capsules.size(), 3u);
  EXPECT_EQ(d.capsules[2].b.x, 6.0f);
  EXPECT_EQ(d.strands, (std::vector<std::uint32_t>{0, 0, 1}));
  EXPECT_TRUE(d.spheres.empty() && d.vertices.empty());
  GeometryData ds = s.geometry(1);
  EXPECT_EQ(ds.type, "sphere");
  EXPECT_TRUE(ds.strands.empty());
  EXPECT_NE(message([&] { s.geometry(2); }).find("geometry 2 does not exist"), std::string::npos);

  // No instances: every geometry once. Capsule ends +- radius, the sphere's ball.
  Box b = s.bounds();
  EXPECT_DOUBLE_EQ(b.lower.x, -0.5);
  EXPECT_DOUBLE_EQ(b.upper.x, 6.0 + double(0.2f));
  EXPECT_DOUBLE_EQ(b.lower.y, -double(0.2f));
  EXPECT_DOUBLE_EQ(b.upper.y, 3.5);
  EXPECT_DOUBLE_EQ(b.lower.z, -0.5);
  // A scaled instance: x stretched by 2, the radius along x with it.
  Scene t;
  t.add_instance(t.add_spheres({&sp, 1}), Transform::scale(2, 1, 1));
  Box tb = t.bounds();
  EXPECT_DOUBLE_EQ(tb.lower.x, -1.0);
  EXPECT_DOUBLE_EQ(tb.upper.x, 1.0);
  EXPECT_DOUBLE_EQ(tb.upper.y, 3.5);
  EXPECT_GT(Scene{}.bounds().lower.x, Scene{}.bounds().upper.x);

  // camera_rays() is camera_rays(camera()); a given pinhole looks where it is told.
  Camera c = s.camera();
  std::vector<Ray> framed = s.camera_rays(4, 3), again = camera_rays(c, 4, 3);
  ASSERT_EQ(framed.size(), 12u);
  EXPECT_EQ(std::memcmp(framed.data(), again.data(), framed.size() * sizeof(Ray)), 0);
  Camera pin;
  pin.eye = {0, 0, -10};
  pin.target = {0, 0, 0};
  pin.fov_y_deg = 90;
  std::vector<Ray> one = camera_rays(pin, 1, 1);
  EXPECT_FLOAT_EQ(one[0].dir.z, 1.0f);
  EXPECT_FLOAT_EQ(one[0].org.z, -10.0f);
  std::vector<Ray> wide = camera_rays(pin, 2, 1); // pixel centres at +-1/2 of tan(45 deg) * aspect 2
  EXPECT_NEAR(std::abs(wide[1].dir.x / wide[1].dir.z), 1.0, 1e-6);
  pin.fov_y_deg = 180;
  EXPECT_NE(message([&] { camera_rays(pin, 2, 2); }).find("fov_y_deg"), std::string::npos);

  // Accel stats: what it traces and the method built; auto names what it kept.
  Accel masq_accel = Accel::build(s, {Method::Masq});
  EXPECT_EQ(masq_accel.stats().method, Method::Masq);
  EXPECT_EQ(masq_accel.stats().primitives, 4u);
  Accel automatic = Accel::build(s, {Method::Auto});
  EXPECT_EQ(automatic.options().method, Method::Auto);
  const Method kept = automatic.stats().method;
  EXPECT_TRUE(kept == Method::Ref || kept == Method::Masq || kept == Method::Cluster || kept == Method::Auto);
}

// Two contexts on two threads at once give the same hits as one context alone: per
// backend (two contexts on the same backend share the device and queue) and mixed.
TEST(Api, TwoContextsOnTwoThreadsMatchOneContext) {
  Scene scene = mixed_scene();
  Accel masq_accel = Accel::build(scene, {Method::Masq});
  Accel ref_accel = Accel::build(scene, {Method::Ref});
  std::vector<Ray> rays = grid_rays(64);
  std::vector<Hit> expected = Context("cpu").trace(masq_accel, rays);
  std::vector<std::pair<std::string, std::string>> pairs = {
      {"cpu", "cpu"}, {"vulkan", "vulkan"}, {"opencl", "opencl"}, {"rayquery", "vulkan"}, {"rtpipeline", "rayquery"},
      {"cpu", "opencl"}};
  for (auto [a, b] : pairs) {
    SCOPED_TRACE(a + " + " + b);
    auto ca = open(a), cb = open(b);
    if (!ca || !cb) continue;
    std::vector<Hit> ha, hb;
    std::string err_a, err_b;
    // Several rounds, alternating the two Accels, so uploads and traces interleave.
    auto work = [&rays, &masq_accel, &ref_accel](Context& c, std::vector<Hit>& out, std::string& err) {
      try {
        for (int round = 0; round < 4; ++round) {
          const Accel& acc = round % 2 ? ref_accel : masq_accel;
          out = c.trace(acc, rays);
        }
        out = c.trace(masq_accel, rays);
      } catch (const std::exception& e) {
        err = e.what();
      }
    };
    std::thread ta(work, std::ref(*ca), std::ref(ha), std::ref(err_a));
    std::thread tb(work, std::ref(*cb), std::ref(hb), std::ref(err_b));
    ta.join();
    tb.join();
    ASSERT_EQ(err_a, "");
    ASSERT_EQ(err_b, "");
    for (std::size_t i = 0; i < rays.size(); ++i) {
      ASSERT_EQ(ha[i].geometry, expected[i].geometry) << a << " ray " << i;
      ASSERT_EQ(hb[i].geometry, expected[i].geometry) << b << " ray " << i;
      ASSERT_NEAR(ha[i].t, expected[i].t, 1e-4f);
      ASSERT_NEAR(hb[i].t, expected[i].t, 1e-4f);
    }
  }
}

TEST(Api, BestContextOpensAndReportsItself) {
  std::string why;
  auto ctx = open("best", &why);
  if (!ctx) GTEST_SKIP() << why;
  EXPECT_FALSE(ctx->backend().empty());
  EXPECT_FALSE(ctx->device().empty());
  EXPECT_FALSE(std::string(version()).empty());
  std::vector<std::string> avail = Context::available_backends();
  EXPECT_FALSE(avail.empty());
}

// Context(backend, device): a device named for one Context opens it there, leaves the
// next Context's choice as it was, and a selector naming nothing (or a host backend
// given a device) is one masq::Error naming it.
TEST(Api, ContextOnANamedDevice) {
  EXPECT_NE(message([] { Context("cpu", "0"); }).find("no device to choose"), std::string::npos);
  EXPECT_NE(message([] { Context("best", "0"); }).find("no device to choose"), std::string::npos);
  EXPECT_NE(message([] { Context("warp", "0"); }).find("unknown backend 'warp'"), std::string::npos);
  std::string why;
  auto plain = open("vulkan", &why);
  if (!plain) GTEST_SKIP() << why;
  const std::string msg = message([] { Context("vulkan", "no-such-gpu"); });
  EXPECT_NE(msg.find("no-such-gpu"), std::string::npos) << msg;
  EXPECT_NE(msg.find("Context device"), std::string::npos) << msg;
  Context by_index("vulkan", "0");
  EXPECT_FALSE(by_index.device().empty());
  // The selector held for that Context only: the next default Context opens as before.
  Context again("vulkan");
  EXPECT_EQ(again.device(), plain->device());
}

// A ribbon through the public API: added with a normal that is not unit length, read
// back as it was added, and hit on every backend and method where the strip is (the
// trapezoid |y - 0.5| <= 0.2 - 0.1 s, s = x + 0.5 in [0, 1], facing -z, the rays' side),
// with its normal, the axial parameter in u and the width coordinate over the
// half-width in v. No pixel centre lies within 1/320 of the strip's edges.
TEST(Api, RibbonsReadBackAndHitWhereTheStripIs) {
  Scene s;
  Ribbon rb{{-0.5f, 0.5f, 0}, 0.2f, {0.5f, 0.5f, 0}, 0.1f, {0, 0, -3}};
  const std::uint32_t g = s.add_ribbons({&rb, 1});
  GeometryData d = s.geometry(g);
  EXPECT_EQ(d.type, "ribbon");
  ASSERT_EQ(d.ribbons.size(), 1u);
  EXPECT_EQ(d.ribbons[0].n.z, -3.0f);
  EXPECT_EQ(d.ribbons[0].r1, 0.1f);
  EXPECT_EQ(d.strands, (std::vector<std::uint32_t>{0}));
  EXPECT_TRUE(d.capsules.empty() && d.curves.empty());

  std::vector<Ray> rays = grid_rays();
  for (Method m : {Method::Ref, Method::Masq, Method::Cluster}) {
    Accel accel = Accel::build(s, {m, Mode::Robust});
    for (const std::string& b : Context::backends()) {
      auto ctx = open(b);
      if (!ctx) continue;
      SCOPED_TRACE(b + " method " + std::to_string(int(m)));
      std::vector<Hit> hits = ctx->trace(accel, rays);
      int expected = 0, got = 0;
      for (std::size_t i = 0; i < rays.size(); ++i) {
        const double x = rays[i].org.x, y = rays[i].org.y, sx = x + 0.5, r = 0.2 - 0.1 * sx;
        const bool in = sx >= 0 && sx <= 1 && std::abs(y - 0.5) <= r;
        expected += in;
        got += hits[i].hit();
        ASSERT_EQ(hits[i].hit(), in) << "ray " << i << " at (" << x << ", " << y << ")";
        if (!in) continue;
        EXPECT_NEAR(hits[i].t, 5.0f, 1e-5f);
        EXPECT_EQ(hits[i].geometry, int(g));
        EXPECT_NEAR(hits[i].normal.z, -1.0f, 1e-6f);
        EXPECT_NEAR(hits[i].u, sx, 1e-5);
        EXPECT_NEAR(hits[i].v, (0.5 - y) / r, 1e-4);
      }
      EXPECT_EQ(got, expected);
      EXPECT_GT(expected, 30);
    }
  }
}
