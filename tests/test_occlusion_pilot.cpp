// The BLAS occlusion order's pilot (bench/occlusion_pilot.h): which structures it is run
// on, and its choice against a backend whose CPU time per trace the test sets by the
// uploaded order.
#include "bench/occlusion_pilot.h"
#include "bvh/twolevel/build_accel.h"
#include "scenes/generators.h"
#include <ctime>
#include <gtest/gtest.h>

using namespace masq;

namespace {

// Spins for `seconds` of this thread's CPU time.
void spin_cpu(double seconds) {
  auto now = [] {
    timespec ts{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
  };
  const double end = now() + seconds;
  while (now() < end) {
  }
}

// A backend whose trace costs the CPU time the test sets for the uploaded order; it
// records the queries it was asked.
class OrderFake : public Backend {
 public:
  double nearest_s = 0, starts_last_s = 0;
  std::vector<Query> queries;
  std::string name() const override { return "fake"; }
  std::string device_name() const override { return "fake"; }
  void set_scene(const PackedScene& s) override { starts_last_ = s.features.blas_starts_last; }
  void trace(std::span<const kernel::Ray>, std::span<kernel::Hit>, std::span<kernel::RayStats>, Query q) override {
    queries.push_back(q);
    spin_cpu(starts_last_ ? starts_last_s : nearest_s);
  }
  TraceTiming timing() const override { return {}; }
  std::size_t device_bytes() const override { return 0; }

 private:
  bool starts_last_ = false;
};

OcclusionOrderChoice choose(double nearest_s, double starts_last_s) {
  OrderFake a, b;
  a.nearest_s = b.nearest_s = nearest_s;
  a.starts_last_s = b.starts_last_s = starts_last_s;
  std::vector<kernel::Ray> rays(100);
  OcclusionOrderChoice c = choose_blas_occlusion(a, b, PackedScene{}, rays, 100, 3, 0.02);
  for (Query q : a.queries) EXPECT_EQ(q, Query::Any);
  for (Query q : b.queries) EXPECT_EQ(q, Query::Any);
  EXPECT_EQ(a.queries.size(), 4u) << "a warm-up and three rounds";
  return c;
}

} // namespace

TEST(OcclusionPilot, KeepsTheFasterOrderByCpuTime) {
  OcclusionOrderChoice faster = choose(0.015, 0.005);
  EXPECT_EQ(faster.order, BlasOcclusion::StartsLast);
  EXPECT_GT(faster.nearest_cpu_s.median, 2.0 * faster.starts_last_cpu_s.median);
  EXPECT_EQ(choose(0.005, 0.015).order, BlasOcclusion::Nearest);
}

TEST(OcclusionPilot, RunsWhereABlasHasInnerNodes) {
  const Scene s = make_default_scene(); // 1,000 capsules over a ground of two triangles
  EXPECT_TRUE(blas_order_matters(build_accel(s, Method::Ref, {})));     // the capsules' BLAS
  EXPECT_TRUE(blas_order_matters(build_accel(s, Method::Cluster, {})));
  EXPECT_FALSE(blas_order_matters(build_accel(s, Method::Masq, {}))) << "entries, and the ground's one-node BLAS";
  const PackedScene ref = build_accel(s, Method::Ref, {});
  EXPECT_TRUE(with_blas_occlusion(ref, BlasOcclusion::StartsLast).features.blas_starts_last);
  EXPECT_FALSE(with_blas_occlusion(ref, BlasOcclusion::Nearest).features.blas_starts_last);
}
