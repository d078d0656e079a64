// The BVH builders of bvh/binary/builder.h: clipped bounds are conservative, SBVH keeps every
// primitive and its budget, reinsertion never raises the SAH cost and keeps a valid
// tree, and every builder traces the same hits as the default on every backend.
#include "bvh/twolevel/build_accel.h"
#include "bvh/binary/builder.h"
#include "bvh/bounds/clip_bounds.h"
#include "bvh/bounds/prim_bounds.h"
#include "bvh/twolevel/structure_cost.h"
#include "host/backend.h"
#include "scenes/camera.h"
#include "masq/error.h"
#include "scenes/generators.h"
#include "tests/random_affine.h"
#include "tests/test_env.h"
#include "tests/random_rays.h"
#include <gtest/gtest.h>
#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>

using namespace masq;
using masq::test::random_rays;

namespace {

const PrimType kAllTypes[] = {PrimType::Capsule, PrimType::RoundCone, PrimType::Sphere, PrimType::Curve, PrimType::Triangle,
                              PrimType::Ribbon};

Geometry random_geometry(PrimType t, int count, std::uint64_t seed) {
  return t == PrimType::Triangle ? make_random_mesh(count, 1.0, seed)
                                 : make_random_geometry(t, count, 0.004f, 0.05f, 1.0, seed);
}

glm::dvec3 random_unit(std::mt19937_64& rng) {
  std::normal_distribution<double> n;
  glm::dvec3 v(n(rng), n(rng), n(rng));
  return v / glm::length(v);
}

// A random point of primitive p (its surface, or inside it: both must be bounded).
glm::dvec3 sample_point(const Geometry& g, std::size_t p, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  double t = u(rng), depth = u(rng) < 0.7 ? 1.0 : u(rng); // mostly on the surface
  switch (g.type) {
    case PrimType::Capsule: {
      const CapsulePrim& c = g.capsules[p];
      return glm::mix(glm::dvec3(c.a), glm::dvec3(c.b), t) + depth * double(c.radius) * random_unit(rng);
    }
    case PrimType::RoundCone: {
      // (1-t)(a + ra u) + t(b + rb u): a point of the hull of the end balls.
      const RoundConePrim& c = g.round_cones[p];
      double r = (1 - t) * c.ra + t * c.rb;
      return glm::mix(glm::dvec3(c.a), glm::dvec3(c.b), t) + depth * r * random_unit(rng);
    }
    case PrimType::Sphere: {
      const SpherePrim& s = g.spheres[p];
      return glm::dvec3(s.center) + depth * double(s.radius) * random_unit(rng);
    }
    case PrimType::Curve: {
      const CurvePrim& c = g.curves[p];
      double s = 1 - t;
      glm::dvec3 b = s * s * s * glm::dvec3(c.p[0]) + 3 * s * s * t * glm::dvec3(c.p[1]) +
                     3 * s * t * t * glm::dvec3(c.p[2]) + t * t * t * glm::dvec3(c.p[3]);
      return b + depth * double(c.radius) * random_unit(rng);
    }
    case PrimType::Ribbon: {
      // On the strip: p0 + t (p1 - p0) + v r(t) w, w the unit width direction (a ribbon
      // whose normal runs along its axis has no surface: its axis point).
      const RibbonPrim& r = g.ribbons[p];
      glm::dvec3 a = glm::dvec3(r.p1) - glm::dvec3(r.p0), w = glm::cross(glm::dvec3(r.n), a);
      double wl = glm::length(w), v = 2 * u(rng) - 1;
      if (wl > 0) w /= wl;
      return glm::dvec3(r.p0) + t * a + v * ((1 - t) * r.r0 + t * r.r1) * w;
    }
    case PrimType::Triangle: {
      const glm::uvec3& tri = g.triangles[p];
      double a = u(rng), b = u(rng);
      if (a + b > 1) a = 1 - a, b = 1 - b;
      return glm::dvec3(g.vertices[tri.x]) + a * (glm::dvec3(g.vertices[tri.y]) - glm::dvec3(g.vertices[tri.x])) +
             b * (glm::dvec3(g.vertices[tri.z]) - glm::dvec3(g.vertices[tri.x]));
    }
  }
  return {};
}

Aabb prim_box(const Geometry& g, std::size_t p) {
  if (g.type != PrimType::Triangle) return hull_box(ball_hull(g, p));
  Aabb b;
  for (int k = 0; k < 3; ++k) b.grow(glm::dvec3(g.vertices[g.triangles[p][k]]));
  return b;
}

bool inside(const Aabb& b, const glm::dvec3& x) {
  return x.x >= b.lo.x && x.x <= b.hi.x && x.y >= b.lo.y && x.y <= b.hi.y && x.z >= b.lo.z && x.z <= b.hi.z;
}

std::vector<Aabb> boxes_of(const Geometry& g) {
  std::vector<Aabb> boxes;
  for (std::size_t p = 0; p < g.primitive_count(); ++p) boxes.push_back(prim_box(g, p));
  return boxes;
}

PrimClipper clipper_of(const Geometry& g) {
  return [&g](int item, int axis, double lo, double hi) { return clip_primitive(g, std::size_t(item), axis, lo, hi); };
}

// Boxes contain their children, leaves partition `order`, every item appears.
void expect_valid_tree(const BinaryBvh& bvh, std::size_t items, bool each_once) {
  ASSERT_FALSE(bvh.nodes.empty());
  std::vector<int> covered(bvh.order.size(), 0), seen(items, 0);
  std::vector<int> stack{0};
  std::size_t visited = 0;
  while (!stack.empty()) {
    const BinaryNode& n = bvh.nodes[std::size_t(stack.back())];
    stack.pop_back();
    ++visited;
    if (n.is_leaf()) {
      for (int i = n.first; i < n.first + n.count; ++i) {
        ++covered[std::size_t(i)];
        ++seen[std::size_t(bvh.order[std::size_t(i)])];
      }
      continue;
    }
    for (int c : {n.left, n.right}) {
      const Aabb& b = bvh.nodes[std::size_t(c)].box;
      for (int k = 0; k < 3; ++k) {
        ASSERT_LE(n.box.lo[k], b.lo[k]);
        ASSERT_GE(n.box.hi[k], b.hi[k]);
      }
      stack.push_back(c);
    }
  }
  EXPECT_EQ(visited, bvh.nodes.size()) << "unreachable nodes";
  for (int c : covered) ASSERT_EQ(c, 1) << "a slot of order is in no leaf or in two";
  for (std::size_t i = 0; i < items; ++i) {
    ASSERT_GE(seen[i], 1) << "item " << i << " is in no leaf";
    if (each_once) {
      ASSERT_EQ(seen[i], 1) << "item " << i << " is in several leaves";
    }
  }
}

} // namespace

TEST(ClipBounds, EveryPointOfThePrimitiveInsideTheSlabIsInsideTheClippedBox) {
  for (PrimType type : kAllTypes) {
    SCOPED_TRACE(prim_type_name(type));
    Geometry g = random_geometry(type, 60, 7 + int(type));
    std::mt19937_64 rng(99 + int(type));
    std::uniform_real_distribution<double> u(0.0, 1.0);
    int in_slab = 0, clipped_smaller = 0;
    for (std::size_t p = 0; p < g.primitive_count(); ++p) {
      Aabb full = prim_box(g, p);
      for (int s = 0; s < 20; ++s) {
        int axis = int(rng() % 3);
        // A slab around a point of the primitive, from thin to wider than the primitive.
        double centre = sample_point(g, p, rng)[axis];
        double half = (full.hi[axis] - full.lo[axis]) * std::pow(10.0, -3.0 * u(rng));
        double lo = centre - half * u(rng), hi = centre + half * u(rng);
        Aabb box = clip_primitive(g, p, axis, lo, hi);
        if (!box.empty()) {
          EXPECT_GE(box.lo[axis], lo);
          EXPECT_LE(box.hi[axis], hi);
          clipped_smaller += box.area() < 0.999 * full.area();
        }
        for (int k = 0; k < 200; ++k) {
          glm::dvec3 x = sample_point(g, p, rng);
          if (x[axis] < lo || x[axis] > hi) continue;
          ++in_slab;
          ASSERT_TRUE(inside(box, x)) << "primitive " << p << " slab axis " << axis << " [" << lo << ", " << hi
                                      << "]: point (" << x.x << ", " << x.y << ", " << x.z << ") outside the clipped box ["
                                      << box.lo.x << " " << box.lo.y << " " << box.lo.z << " | " << box.hi.x << " "
                                      << box.hi.y << " " << box.hi.z << "]";
        }
      }
    }
    EXPECT_GT(in_slab, 10000);
    EXPECT_GT(clipped_smaller, 100) << "clipping should usually shrink the box";
  }
}

TEST(ClipBounds, MissedSlabGivesAnEmptyBox) {
  EXPECT_TRUE(clip_segment({0, 0, 0}, 0.1, {1, 0, 0}, 0.1, 0, 2.0, 3.0).empty());
  EXPECT_TRUE(clip_sphere({0, 0, 0}, 1.0, 1, 1.5, 2.0).empty());
  EXPECT_TRUE(clip_triangle({glm::dvec3(0, 0, 0), glm::dvec3(1, 0, 0), glm::dvec3(0, 1, 0)}, 2, 0.1, 0.2).empty());
  EXPECT_TRUE(clip_curve({glm::dvec3(0, 0, 0), glm::dvec3(1, 1, 0), glm::dvec3(2, 1, 0), glm::dvec3(3, 0, 0)}, 0.01, 1, 0.8,
                         2.0)
                  .empty()); // the curve peaks at y = 0.75
}

TEST(Sbvh, KeepsEveryPrimitiveWithinTheBudgetAndCoversIt) {
  for (PrimType type : kAllTypes) {
    for (double budget : {1.0, 1.3, 2.0}) {
      SCOPED_TRACE(std::string(prim_type_name(type)) + " budget " + std::to_string(budget));
      Geometry g = random_geometry(type, 400, 17 + int(type));
      std::vector<Aabb> boxes = boxes_of(g);
      SbvhOptions so;
      so.max_refs = budget;
      SbvhStats st;
      BinaryBvh bvh = build_sbvh(boxes, clipper_of(g), {}, so, &st);
      expect_valid_tree(bvh, boxes.size(), false);
      EXPECT_EQ(st.references, bvh.order.size());
      EXPECT_LE(double(bvh.order.size()), budget * double(boxes.size()));
      if (budget > 1.0 && type != PrimType::Sphere) {
        EXPECT_GT(st.spatial_splits, 0u);
      }
      // Coverage: every point of a primitive lies in a leaf that names it.
      std::vector<std::vector<const Aabb*>> leaves_of(boxes.size());
      for (const BinaryNode& n : bvh.nodes)
        if (n.is_leaf())
          for (int i = n.first; i < n.first + n.count; ++i) leaves_of[std::size_t(bvh.order[std::size_t(i)])].push_back(&n.box);
      std::mt19937_64 rng(5);
      for (std::size_t p = 0; p < boxes.size(); ++p)
        for (int k = 0; k < 100; ++k) {
          glm::dvec3 x = sample_point(g, p, rng);
          bool found = false;
          for (const Aabb* b : leaves_of[p]) found = found || inside(*b, x);
          ASSERT_TRUE(found) << "a point of primitive " << p << " is in none of its " << leaves_of[p].size() << " leaves";
        }
    }
  }
}

TEST(Sbvh, LowersTheSahCostOfLongDiagonalPrimitives) {
  // Long thin parallel capsules diagonal to the axes (a tilted strand bundle): their
  // AABBs overlap whatever the object split, while a plane cuts them into thinner pieces.
  Geometry g;
  g.type = PrimType::Capsule;
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  for (int i = 0; i < 500; ++i) {
    glm::vec3 o(u(rng), u(rng), u(rng)), d(0.7f, 0.7f, 0.1f);
    g.capsules.push_back({o - d, o + d, 0.003f});
  }
  std::vector<Aabb> boxes = boxes_of(g);
  double sah = binary_sah_cost(build_binned_sah(boxes));
  SbvhStats st;
  double sbvh = binary_sah_cost(build_sbvh(boxes, clipper_of(g), {}, {}, &st));
  SbvhOptions none;
  none.max_refs = 1.0;
  double sbvh1 = binary_sah_cost(build_sbvh(boxes, clipper_of(g), {}, none));
  std::printf("  SAH cost: binned %.2f, sbvh %.2f (%zu references for %zu capsules, %zu spatial splits), no budget %.2f\n",
              sah, sbvh, st.references, boxes.size(), st.spatial_splits, sbvh1);
  EXPECT_LT(sbvh, 0.9 * sah);
  // The binned SAH keeps its boxes in fp32, rounded outward; SBVH in double: the same
  // tree, its cost within fp32's rounding of the boxes.
  EXPECT_NEAR(sbvh1, sah, 1e-6 * sah) << "without a budget SBVH is the binned SAH";
}

TEST(Sbvh, RejectsBadOptions) {
  std::vector<Aabb> boxes(3);
  for (int i = 0; i < 3; ++i) boxes[std::size_t(i)].grow(glm::dvec3(i)), boxes[std::size_t(i)].grow(glm::dvec3(i + 1));
  PrimClipper clip = [&](int i, int, double, double) { return boxes[std::size_t(i)]; };
  SbvhOptions so;
  so.max_refs = 0.5;
  EXPECT_THROW(build_sbvh(boxes, clip, {}, so), Error);
  EXPECT_THROW(parse_builder("spatial"), Error);
  EXPECT_EQ(parse_builder("sbvh+reinsert"), Builder::SbvhReinsert);
}

// sah4 prices a leaf per block of four primitives: on unit cubes in a row, where the
// per-primitive SAH (C_t = C_i = 1) stops at pairs (a pair's leaf costs 2, its split
// 2.2), blocks of four make every leaf hold four (one block costs 1, its split 2.1).
TEST(Sah4, LeafBlocksOfFourFillLeaves) {
  std::vector<Aabb> row(64);
  for (int i = 0; i < 64; ++i) {
    row[std::size_t(i)].grow(glm::dvec3(i, 0, 0));
    row[std::size_t(i)].grow(glm::dvec3(i + 1, 1, 1));
  }
  auto leaf_sizes = [](const BinaryBvh& bvh) {
    std::vector<int> sizes;
    for (const BinaryNode& n : bvh.nodes)
      if (n.is_leaf()) sizes.push_back(n.count);
    return sizes;
  };
  SahOptions per_prim;
  SahOptions blocks = per_prim;
  blocks.leaf_block = 4;
  EXPECT_EQ(leaf_sizes(build_binned_sah(row, per_prim)), std::vector<int>(32, 2));
  EXPECT_EQ(leaf_sizes(build_binned_sah(row, blocks)), std::vector<int>(16, 4));
  // Through the builder: only sah4 sets the block.
  PrimClipper clip = [&](int i, int, double, double) { return row[std::size_t(i)]; };
  BuilderOptions b4;
  b4.kind = parse_builder("sah4");
  EXPECT_EQ(b4.kind, Builder::Sah4);
  EXPECT_EQ(leaf_sizes(build_blas_binary(row, clip, per_prim, b4)), std::vector<int>(16, 4));
  EXPECT_EQ(leaf_sizes(build_blas_binary(row, clip, per_prim, BuilderOptions{})), std::vector<int>(32, 2));
  SahOptions bad = per_prim;
  bad.leaf_block = 0;
  EXPECT_THROW(build_binned_sah(row, bad), Error);
}

// sah-priced prices a leaf primitive at its type's intersector cost against a box step
// (capsule 5, curve 30): on the row of unit cubes (here balls: capsules of length 0) a
// pair's leaf costs 10 and its split 1 + 5 * 12/10 = 7, so every leaf holds one capsule,
// where the per-primitive SAH stops at pairs. The TLAS and cluster BLAS are not priced.
TEST(SahPriced, CapsuleLeavesHoldOnePrimitive) {
  EXPECT_DOUBLE_EQ(blas_isect_price(MASQ_PRIM_CAPSULE), 5.0);
  EXPECT_DOUBLE_EQ(blas_isect_price(MASQ_PRIM_CURVE), 30.0);
  EXPECT_EQ(parse_builder("sah-priced"), Builder::SahPriced);
  Scene s;
  Geometry g;
  g.type = PrimType::Capsule;
  for (int i = 0; i < 64; ++i) {
    glm::vec3 c(float(i) + 0.5f, 0.5f, 0.5f);
    g.capsules.push_back({c, c, 0.5f});
  }
  s.geometries.push_back(g);
  s.instances.push_back({0, {}});
  AccelOptions plain, priced;
  priced.builder.kind = Builder::SahPriced;
  EXPECT_EQ(build_accel(s, Method::Ref, plain).stats.blas_leaves, 32u);
  EXPECT_EQ(build_accel(s, Method::Ref, priced).stats.blas_leaves, 64u);
  // Only BLAS over primitives: masq's TLAS and the cluster BLAS come out the same.
  for (Method m : {Method::Masq, Method::Cluster}) {
    BuildStats a = build_accel(s, m, plain).stats, b = build_accel(s, m, priced).stats;
    EXPECT_EQ(a.sah_cost, b.sah_cost) << method_name(m);
    EXPECT_EQ(a.blas_leaves, b.blas_leaves) << method_name(m);
    EXPECT_EQ(a.blas_sah_cost, b.blas_sah_cost) << method_name(m);
  }
}

// sah4 prices a TLAS of compact masquerade entries alone per block of four, as the cpu
// tests a leaf's unit boxes four at a time; a TLAS of 64-byte instances keeps the
// per-entry price. On a row of short capsules (their boxes apart, as the unit cubes
// above): leaves of four entries against pairs.
TEST(Sah4, CompactEntryTlasLeavesHoldFour) {
  Scene s;
  Geometry g;
  g.type = PrimType::Capsule;
  for (int i = 0; i < 64; ++i)
    g.capsules.push_back({glm::vec3(float(i) + 0.25f, 0.5f, 0.5f), glm::vec3(float(i) + 0.75f, 0.5f, 0.5f), 0.2f});
  s.geometries.push_back(g);
  s.instances.push_back({0, {}});
  AccelOptions per_entry, blocks;
  blocks.builder.kind = Builder::Sah4;
  const PackedScene compact_sah = build_accel(s, Method::Masq, per_entry);
  ASSERT_EQ(compact_sah.masq_instances.size(), 64u);
  EXPECT_EQ(compact_sah.stats.tlas_leaves, 32u);
  EXPECT_EQ(build_accel(s, Method::Masq, blocks).stats.tlas_leaves, 16u);
  AccelOptions full = blocks;
  full.masq_instances = MasqInstances::Full;
  const PackedScene full_sah4 = build_accel(s, Method::Masq, full);
  ASSERT_EQ(full_sah4.instances.size(), 64u);
  EXPECT_EQ(full_sah4.stats.tlas_leaves, 32u);
}

TEST(Reinsertion, NeverRaisesTheCostKeepsEveryItemOnceAndImprovesABadTree) {
  for (std::uint64_t seed : {1u, 2u, 3u}) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    // Instance-like boxes of mixed sizes: a TLAS.
    std::vector<Aabb> boxes;
    for (int i = 0; i < 3000; ++i) {
      glm::dvec3 c(u(rng), u(rng), u(rng));
      glm::dvec3 e = glm::dvec3(u(rng), u(rng), u(rng)) * (u(rng) < 0.1 ? 0.2 : 0.01);
      Aabb b;
      b.grow(c - e);
      b.grow(c + e);
      boxes.push_back(b);
    }
    for (int bins : {16, 2}) { // 2 bins: a poor tree with much to gain
      SahOptions sah;
      sah.bins = bins;
      BinaryBvh in = build_binned_sah(boxes, sah);
      ReinsertStats st;
      BinaryBvh out = reinsert_optimize(in, sah, {}, &st);
      SCOPED_TRACE("seed " + std::to_string(seed) + " bins " + std::to_string(bins));
      expect_valid_tree(out, boxes.size(), true);
      EXPECT_EQ(out.order.size(), boxes.size());
      for (const BinaryNode& n : out.nodes)
        if (n.is_leaf())
          for (int i = n.first; i < n.first + n.count; ++i) {
            const Aabb& b = boxes[std::size_t(out.order[std::size_t(i)])];
            for (int k = 0; k < 3; ++k) ASSERT_TRUE(n.box.lo[k] <= b.lo[k] && n.box.hi[k] >= b.hi[k]);
          }
      double before = binary_sah_cost(in, sah), after = binary_sah_cost(out, sah);
      EXPECT_DOUBLE_EQ(st.cost_before, before);
      EXPECT_DOUBLE_EQ(st.cost_after, after);
      EXPECT_LE(after, before);
      if (bins == 2) {
        EXPECT_LT(after, 0.95 * before) << "a 2-bin tree should improve by > 5%";
      }
      EXPECT_EQ(st.depth_before, binary_depth_of(in));
      EXPECT_EQ(st.depth_after, binary_depth_of(out));
      EXPECT_LE(st.depth_after, st.depth_before + ReinsertOptions{}.max_extra_depth);
      ReinsertOptions flat;
      flat.max_extra_depth = 0;
      ReinsertStats fst;
      BinaryBvh same_depth = reinsert_optimize(in, sah, flat, &fst);
      EXPECT_LE(binary_depth_of(same_depth), binary_depth_of(in));
      EXPECT_LE(binary_sah_cost(same_depth, sah), before);
      std::printf("  seed %d bins %2d: SAH %.2f -> %.2f (%zu moves, %d passes, depth %d -> %d; depth kept: SAH %.2f)\n",
                  int(seed), bins, before, after, st.moves, st.passes, st.depth_before, st.depth_after, fst.cost_after);
    }
  }
}

TEST(Reinsertion, WorksOnSbvhTreesWithDuplicateReferences) {
  Geometry g = random_geometry(PrimType::Capsule, 500, 8);
  std::vector<Aabb> boxes = boxes_of(g);
  BinaryBvh in = build_sbvh(boxes, clipper_of(g));
  ASSERT_GT(in.order.size(), boxes.size());
  BinaryBvh out = reinsert_optimize(in);
  expect_valid_tree(out, boxes.size(), false);
  EXPECT_EQ(out.order.size(), in.order.size());
  EXPECT_LE(binary_sah_cost(out), binary_sah_cost(in));
}

// ---- Every builder traces what the default builder traces -------------------------

namespace {


// Long thin triangles in every direction: their boxes overlap, so spatial splits cut
// them (a bumpy grid sheet gives SBVH nothing to do).
Geometry random_slivers(int count, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  Geometry g;
  g.type = PrimType::Triangle;
  for (int i = 0; i < count; ++i) {
    glm::vec3 a(u(rng), u(rng), u(rng)), d(u(rng), u(rng), u(rng)), w(u(rng), u(rng), u(rng));
    std::uint32_t k = std::uint32_t(g.vertices.size());
    g.vertices.push_back(a);
    g.vertices.push_back(a + d);
    g.vertices.push_back(a + 0.05f * w);
    g.triangles.push_back({k, k + 1, k + 2});
  }
  return g;
}

class EveryBuilder : public ::testing::TestWithParam<PrimType> {};

} // namespace

TEST_P(EveryBuilder, SameHitsAsTheDefaultBuilderOnEveryBackend) {
  PrimType type = GetParam();
  std::mt19937_64 rng(61 + int(type));
  Scene s;
  s.name = std::string("random ") + prim_type_key(type);
  s.geometries.push_back(type == PrimType::Triangle ? random_slivers(300, 71) : random_geometry(type, 300, 71 + int(type)));
  s.geometries.push_back(random_slivers(100, 43));
  for (int i = 0; i < 3; ++i) s.instances.push_back({0, masq::test::random_affine(rng)});
  s.instances.push_back({1, masq::test::random_affine(rng)});
  std::vector<kernel::Ray> rays = random_rays(rng, 1024);
  for (const std::string& name : backend_names()) {
    if (driver_traversal(name)) continue; // the driver builds its own BVH: the builder does not reach it
    std::unique_ptr<Backend> be =
        masq::test::open_or_fail(name, [](const std::string& n) { return make_backend(n); });
    if (!be) continue;
    for (Method m : {Method::Ref, Method::Masq, Method::Cluster, Method::Auto}) {
      std::vector<kernel::Hit> base[2];
      for (Builder b : all_builders()) {
        SCOPED_TRACE(name + " " + method_name(m) + " " + builder_name(b) + " on " + s.name);
        AccelOptions opt;
        opt.builder.kind = b;
        PackedScene ps = build_accel(s, m, opt);
        // Spheres' boxes are already tight: spatial splits rarely pay there, but the
        // slivers beside them always get some (so duplicate references are traced).
        if (builder_splits(b) && m == Method::Ref) {
          EXPECT_GT(ps.stats.blas_references, ps.stats.blas_primitives) << "no spatial split in a BLAS";
        }
        if (builder_splits(b)) {
          EXPECT_LE(ps.stats.blas_references, 2 * ps.stats.blas_primitives);
        }
        be->set_scene(ps);
        for (int q = 0; q < 2; ++q) {
          std::vector<kernel::Hit> hits(rays.size());
          be->trace(rays, hits, {}, q == 0 ? Query::Closest : Query::Any);
          if (b == Builder::Sah) {
            base[q] = hits;
            continue;
          }
          int differ = 0, hits_seen = 0;
          std::string first;
          for (std::size_t i = 0; i < rays.size(); ++i) {
            const kernel::Hit &h = hits[i], &r = base[q][i];
            hits_seen += r.prim >= 0;
            bool same = (h.prim >= 0) == (r.prim >= 0);
            // Closest: the same primitive at the same t (the same intersector runs on the
            // same ray). Any hit: only whether something was hit is defined.
            if (same && q == 0 && r.prim >= 0)
              same = h.prim == r.prim && h.geom == r.geom && h.inst == r.inst && std::abs(h.t - r.t) <= 1e-6f * r.t;
            if (!same && differ++ == 0)
              first = "ray " + std::to_string(i) + ": default prim " + std::to_string(r.prim) + " geom " +
                      std::to_string(r.geom) + " inst " + std::to_string(r.inst) + " t " + std::to_string(r.t) + ", got prim " +
                      std::to_string(h.prim) + " geom " + std::to_string(h.geom) + " inst " + std::to_string(h.inst) +
                      " t " + std::to_string(h.t);
          }
          EXPECT_GT(hits_seen, int(rays.size() / 20));
          EXPECT_EQ(differ, 0) << (q == 0 ? "closest: " : "any hit: ") << first;
        }
      }
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Types, EveryBuilder, ::testing::ValuesIn(kAllTypes),
                         [](const auto& param_info) { return std::string(prim_type_key(param_info.param)); });

// build_binned_sah_costs: each tree is, byte for byte, the one build_binned_sah builds with
// that traversal cost alone (auto's cluster shapes of one size take their BLAS from it).
TEST(BinnedSahCosts, EachTreeIsItsOwnBuild) {
  std::mt19937_64 rng(17);
  std::uniform_real_distribution<double> u(-1.0, 1.0), w(0.0, 0.05);
  for (int n : {1, 2, 5, 37, 300, 5000}) {
    for (int coarse : {0, 1}) { // coarse: coordinates on a grid of 1/8, many equal and coincident
      std::vector<Aabb> boxes(static_cast<std::size_t>(n));
      for (Aabb& b : boxes) {
        glm::dvec3 c(u(rng), u(rng), u(rng)), e(w(rng), w(rng), w(rng));
        if (coarse) c = glm::round(c * 8.0) / 8.0, e = glm::dvec3(0.0625);
        b.lo = c - e;
        b.hi = c + e;
      }
      for (int block : {1, 4}) {
        SahOptions opt;
        opt.leaf_block = block;
        const std::vector<double> costs = {4.0, 1.0, 2.5};
        std::vector<BinaryBvh> trees = build_binned_sah_costs(boxes, opt, costs);
        ASSERT_EQ(trees.size(), costs.size());
        for (std::size_t t = 0; t < costs.size(); ++t) {
          SCOPED_TRACE("n " + std::to_string(n) + (coarse ? " coarse" : "") + " block " + std::to_string(block) +
                       " cost " + std::to_string(costs[t]));
          SahOptions one = opt;
          one.traversal_cost = costs[t];
          BinaryBvh alone = build_binned_sah(boxes, one);
          ASSERT_EQ(trees[t].nodes.size(), alone.nodes.size());
          EXPECT_EQ(std::memcmp(trees[t].nodes.data(), alone.nodes.data(), alone.nodes.size() * sizeof(BinaryNode)), 0);
          EXPECT_TRUE(std::equal(alone.order.begin(), alone.order.end(), trees[t].order.begin(), trees[t].order.end()));
        }
        EXPECT_LE(trees[0].nodes.size(), trees[1].nodes.size()); // a dearer step stops splitting sooner
      }
    }
  }
}
