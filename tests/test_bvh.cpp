// Binned SAH + wide collapse: every primitive lands in exactly one leaf, every child
// box (fp32, rounded outward) contains its subtree, traversal stack needs fit.
#include "bvh/twolevel/build_accel.h"
#include "bvh/nodes/wide_bvh.h"
#include "kernels/variants.h"
#include "scenes/generators.h"
#include <gtest/gtest.h>
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

using namespace masq;

namespace {

struct Check {
  const PackedScene& ps;
  const std::vector<Aabb>& prim_boxes;
  std::vector<int> seen;
  void node(int index, const Aabb& parent_box) {
    const kernel::WideNode& n = ps.nodes[index];
    for (int s = 0; s < MASQ_WIDTH; ++s) {
      if (n.count[s] < 0) continue;
      Aabb child;
      child.lo = {n.lo_x[s], n.lo_y[s], n.lo_z[s]};
      child.hi = {n.hi_x[s], n.hi_y[s], n.hi_z[s]};
      EXPECT_LE(parent_box.lo.x, child.lo.x + 1e-6);
      if (n.count[s] == 0) {
        node(n.child[s], child);
        continue;
      }
      for (int j = 0; j < n.count[s]; ++j) {
        int prim = ps.refs[n.child[s] + j];
        ++seen[prim];
        const Aabb& pb = prim_boxes[prim];
        EXPECT_LE(child.lo.x, pb.lo.x);
        EXPECT_LE(child.lo.y, pb.lo.y);
        EXPECT_LE(child.lo.z, pb.lo.z);
        EXPECT_GE(child.hi.x, pb.hi.x);
        EXPECT_GE(child.hi.y, pb.hi.y);
        EXPECT_GE(child.hi.z, pb.hi.z);
      }
    }
  }
};

} // namespace

TEST(Bvh, EveryCapsuleInExactlyOneLeafAndInsideItsBox) {
  Scene s;
  s.geometries.push_back(make_random_capsules(5000, 0.001f, 0.02f, 1.0, 7));
  s.instances.push_back({0, {}});
  PackedScene ps = build_accel(s, Method::Ref);
  std::vector<Aabb> boxes;
  for (const CapsulePrim& c : s.geometries[0].capsules) {
    Aabb b;
    b.grow(glm::dvec3(c.a) - glm::dvec3(c.radius));
    b.grow(glm::dvec3(c.a) + glm::dvec3(c.radius));
    b.grow(glm::dvec3(c.b) - glm::dvec3(c.radius));
    b.grow(glm::dvec3(c.b) + glm::dvec3(c.radius));
    boxes.push_back(b);
  }
  Check check{ps, boxes, std::vector<int>(boxes.size(), 0)};
  // BLAS root is the first node appended (the TLAS comes after it).
  Aabb everything;
  everything.lo = glm::dvec3(-1e30);
  everything.hi = glm::dvec3(1e30);
  check.node(0, everything);
  EXPECT_TRUE(std::all_of(check.seen.begin(), check.seen.end(), [](int k) { return k == 1; }));
  EXPECT_GT(ps.stats.blas_sah_cost, 1.0);
  EXPECT_GT(ps.stats.blas_nodes, 5000u / 16u);
  EXPECT_EQ(ps.stats.instances, 1u);
}

TEST(Bvh, CoincidentPrimitivesStillSplitIntoSmallLeaves) {
  std::vector<Aabb> boxes(1000);
  for (Aabb& b : boxes) {
    b.lo = glm::dvec3(0.0);
    b.hi = glm::dvec3(1.0);
  }
  BinaryBvh bvh = build_binned_sah(boxes);
  for (const BinaryNode& n : bvh.nodes) {
    if (n.is_leaf()) {
      EXPECT_LE(n.count, 4);
    }
  }
  HugePageVector<kernel::WideNode> nodes;
  HugePageVector<std::int32_t> refs;
  std::vector<std::int32_t> ids(1000);
  for (int i = 0; i < 1000; ++i) ids[i] = i;
  WideBvhInfo info = append_wide_bvh(bvh, ids, nodes, refs);
  EXPECT_EQ(refs.size(), 1000u);
  EXPECT_LE(info.stack_need, MASQ_STACK_MAX);
}

TEST(Bvh, MasqueradeMakesOneInstancePerCapsule) {
  Scene s = make_default_scene();
  PackedScene ref = build_accel(s, Method::Ref);
  PackedScene masq = build_accel(s, Method::Masq);
  EXPECT_EQ(ref.instances.size(), 2u);
  EXPECT_EQ(masq.tlas_entry_count(), 1001u); // 1000 capsules + the ground plane's BLAS instance
  EXPECT_EQ(masq.instances.size(), 1u);      // the BLAS instance; the capsules are compact entries
  EXPECT_EQ(masq.masq_instances.size(), 1000u);
  EXPECT_EQ(masq.masq_owners.size(), 1u);
  EXPECT_EQ(masq.tlas_leaf_order.size(), masq.tlas_entry_count());
  EXPECT_EQ(masq.stats.instances, masq.tlas_entry_count());
  EXPECT_EQ(sizeof(kernel::Instance), 64u);
  EXPECT_EQ(sizeof(kernel::MasqInstance), 32u);
  AccelOptions full;
  full.masq_instances = MasqInstances::Full;
  PackedScene masq64 = build_accel(s, Method::Masq, full);
  EXPECT_EQ(masq64.instances.size(), 1001u);
  EXPECT_TRUE(masq64.masq_instances.empty());
  // 32 bytes less per capsule, plus one owner (the TLAS nodes may differ: other boxes).
  EXPECT_EQ((masq64.acceleration_bytes() - masq64.node_bytes()) - (masq.acceleration_bytes() - masq.node_bytes()),
            1000u * 32u - 16u);
}

// round_down and round_up step on the float's bits: they must be nextafter's answer on
// every side of zero, at float-exact values, at the fp32 range's ends and beyond it.
TEST(FloatRounding, OutwardAsNextafter) {
  const float inf = std::numeric_limits<float>::infinity();
  auto expect_down = [&](double x) {
    float f = float(x);
    if (double(f) > x) f = std::nextafter(f, -inf);
    EXPECT_EQ(std::bit_cast<std::uint32_t>(round_down(x)), std::bit_cast<std::uint32_t>(f)) << x;
  };
  auto expect_up = [&](double x) {
    float f = float(x);
    if (double(f) < x) f = std::nextafter(f, inf);
    EXPECT_EQ(std::bit_cast<std::uint32_t>(round_up(x)), std::bit_cast<std::uint32_t>(f)) << x;
  };
  std::vector<double> xs = {0.0, -0.0, 1e-300, -1e-300, 1e-45, -1e-45, 0.1, -0.1, 1.0, -1.0, 3.0, -3.0,
                            double(std::numeric_limits<float>::max()), -double(std::numeric_limits<float>::max()),
                            3.5e38, -3.5e38, 1e300, -1e300, std::numeric_limits<double>::infinity(),
                            -std::numeric_limits<double>::infinity()};
  std::uint64_t state = 12345;
  for (int i = 0; i < 20000; ++i) { // random doubles over many exponents, both signs
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    const double m = double(state >> 11) / double(1ull << 53);
    xs.push_back((i & 1 ? -1.0 : 1.0) * std::ldexp(m, int(state % 300) - 150));
  }
  for (double x : xs) {
    expect_down(x);
    expect_up(x);
  }
  // round_down_lanes: round_down's bits in every lane, four values at a time.
  for (std::size_t i = 0; i + 4 <= xs.size(); i += 4) {
    const RoundFloat4 f = round_down_lanes(RoundDouble4{xs[i], xs[i + 1], xs[i + 2], xs[i + 3]});
    for (int k = 0; k < 4; ++k)
      EXPECT_EQ(std::bit_cast<std::uint32_t>(f[k]), std::bit_cast<std::uint32_t>(round_down(xs[i + std::size_t(k)])))
          << xs[i + std::size_t(k)];
  }
}
