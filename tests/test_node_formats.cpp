// Node formats (bvh/nodes/wide_bvh.h, bvh/nodes/quant_node.h): the q8 quantisation is conservative
// for every kind of box, each format reaches every primitive exactly once through boxes
// that contain it, and the traversal stack bound the builder proves holds for 4 and 8
// children.
#include "bvh/twolevel/build_accel.h"
#include "bvh/nodes/quant_node.h"
#include "bvh/nodes/wide_bvh.h"
#include "kernels/variants.h"
#include "masq/error.h"
#include "scenes/generators.h"
#include <gtest/gtest.h>
#include <algorithm>
#include <bit>
#include <cfloat>
#include <cstring>
#include <cmath>
#include <functional>
#include <random>

using namespace masq;

namespace {

float step_of(int biased) { return std::bit_cast<float>(std::uint32_t(biased) << 23); }

// The kernel's decode evaluated both ways a compiler may: product then sum (two
// roundings, the product exact), and one fused multiply-add.
float decode_separate(float origin, int biased, unsigned q) {
  volatile float product = float(q) * step_of(biased);
  volatile float sum = origin + product;
  return sum;
}
float decode_fused(float origin, int biased, unsigned q) { return std::fma(float(q), step_of(biased), origin); }
float flushed(float x) { return std::fabs(x) < FLT_MIN ? std::copysign(0.0f, x) : x; }

struct Violations {
  int count = 0;
  std::string first;
};

// Every decode of the quantised planes must enclose the exact child box.
void check_contains(const QuantFrame& f, const QuantBox& q, const Aabb& child, Violations& v, const std::string& what) {
  for (int k = 0; k < 3; ++k) {
    const float o = f.origin[std::size_t(k)];
    const int e = f.biased_exp[std::size_t(k)];
    for (float lo : {decode_separate(o, e, q.lo[std::size_t(k)]), decode_fused(o, e, q.lo[std::size_t(k)])})
      for (float l : {lo, flushed(lo)})
        if (!(double(l) <= child.lo[k]) && v.count++ == 0)
          v.first = what + ": axis " + std::to_string(k) + " decoded lo " + std::to_string(l) + " > " +
                    std::to_string(child.lo[k]);
    for (float hi : {decode_separate(o, e, q.hi[std::size_t(k)]), decode_fused(o, e, q.hi[std::size_t(k)])})
      for (float h : {hi, flushed(hi)})
        if (!(double(h) >= child.hi[k]) && v.count++ == 0)
          v.first = what + ": axis " + std::to_string(k) + " decoded hi " + std::to_string(h) + " < " +
                    std::to_string(child.hi[k]);
  }
}

// Boxes within [lo, hi] on each axis: random sub-intervals, flat, degenerate, points.
std::vector<Aabb> children_in(std::mt19937_64& rng, const glm::dvec3& lo, const glm::dvec3& hi, int n) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<Aabb> out;
  for (int i = 0; i < n; ++i) {
    Aabb b;
    int kind = i % 4; // 0: box, 1: flat on one axis, 2: single point, 3: touching the node's corner
    for (int k = 0; k < 3; ++k) {
      double a = lo[k] + (hi[k] - lo[k]) * u(rng);
      double c = lo[k] + (hi[k] - lo[k]) * u(rng);
      if (kind == 2 || (kind == 1 && k == i % 3)) c = a;
      if (kind == 3) {
        a = i % 2 ? lo[k] : hi[k];
        c = a;
      }
      b.lo[k] = std::min(a, c);
      b.hi[k] = std::max(a, c);
    }
    out.push_back(b);
  }
  return out;
}

struct Case {
  std::string name;
  glm::dvec3 center;
  glm::dvec3 extent;
};

std::vector<Case> adversarial_cases() {
  return {
      {"unit", {0, 0, 0}, {1, 1, 1}},
      {"huge", {0, 0, 0}, {3e38, 3e38, 3e38}},
      {"huge offset", {3e38, -3e38, 1e38}, {1e37, 1e36, 1e30}},
      {"tiny", {0, 0, 0}, {1e-38, 1e-40, 1e-44}},
      {"tiny off zero", {1e-37, -1e-37, 3e-38}, {1e-38, 1e-39, 1e-45}},
      {"far from origin", {1e7, -3e7, 5e8}, {1e-3, 1.0, 37.0}},
      {"far, sub-ulp extent", {16777217.0, -1e9, 1e20}, {0.25, 1e-5, 1.0}},
      {"flat node", {1.5, -2.5, 0.1}, {0.0, 2.0, 0.0}},
      {"point node", {-7.3, 1e-3, 4e6}, {0.0, 0.0, 0.0}},
      {"mixed magnitudes", {1e-30, 1e10, -1e20}, {1e-30, 1e-3, 1e25}},
      {"straddling zero", {0.0, 0.0, 0.0}, {2e-38, 1.0, 1e38}},
  };
}

TEST(QuantNode, DecodedBoxesContainChildrenForAdversarialBoxes) {
  std::mt19937_64 rng(1);
  Violations v;
  int checked = 0;
  for (const Case& c : adversarial_cases()) {
    glm::dvec3 lo = c.center - 0.5 * c.extent, hi = c.center + 0.5 * c.extent;
    for (int rep = 0; rep < 50; ++rep) {
      std::vector<Aabb> kids = children_in(rng, lo, hi, 8);
      Aabb node;
      for (const Aabb& b : kids) node.grow(b);
      QuantFrame f = quant_frame(node);
      for (const Aabb& b : kids) {
        check_contains(f, quantize_box(f, b), b, v, c.name);
        ++checked;
      }
    }
  }
  EXPECT_EQ(v.count, 0) << v.first;
  EXPECT_EQ(checked, int(adversarial_cases().size()) * 50 * 8);
}

TEST(QuantNode, DecodedBoxesContainChildrenForRandomBoxesAndStayTight) {
  std::mt19937_64 rng(2);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::uniform_int_distribution<int> mag(-40, 38);
  Violations v;
  double worst_slack = 0; // decoded width minus exact width, in quantisation steps
  for (int rep = 0; rep < 20000; ++rep) {
    glm::dvec3 center(u(rng) * std::pow(10.0, mag(rng)), u(rng) * std::pow(10.0, mag(rng)), u(rng) * std::pow(10.0, mag(rng)));
    glm::dvec3 extent(std::pow(10.0, mag(rng)), std::pow(10.0, mag(rng)), std::pow(10.0, mag(rng)));
    extent = glm::min(extent, glm::dvec3(1e38));
    std::vector<Aabb> kids = children_in(rng, center - 0.5 * extent, center + 0.5 * extent, 8);
    Aabb node;
    for (const Aabb& b : kids) node.grow(b);
    QuantFrame f = quant_frame(node);
    for (const Aabb& b : kids) {
      QuantBox q = quantize_box(f, b);
      check_contains(f, q, b, v, "random " + std::to_string(rep));
      for (int k = 0; k < 3; ++k) {
        double step = step_of(f.biased_exp[std::size_t(k)]);
        // Ignore axes where the origin's own rounding dominates (steps below its ulp).
        if (step < 4.0 * std::abs(double(f.origin[std::size_t(k)])) * FLT_EPSILON) continue;
        double slack = (double(q.hi[std::size_t(k)]) - double(q.lo[std::size_t(k)])) - (b.hi[k] - b.lo[k]) / step;
        worst_slack = std::max(worst_slack, slack);
      }
    }
  }
  EXPECT_EQ(v.count, 0) << v.first;
  // Outward rounding costs at most one step per side (plus a fix-up step each).
  EXPECT_LE(worst_slack, 4.0);
}

// The check above can fail: quantising to the nearest plane, as a careless encoder
// would, puts decoded planes inside the true boxes.
TEST(QuantNode, NearestRoundingWouldBeCaught) {
  std::mt19937_64 rng(3);
  Violations v;
  for (int rep = 0; rep < 200; ++rep) {
    std::vector<Aabb> kids = children_in(rng, glm::dvec3(-1.0), glm::dvec3(1.0), 8);
    Aabb node;
    for (const Aabb& b : kids) node.grow(b);
    QuantFrame f = quant_frame(node);
    for (const Aabb& b : kids) {
      QuantBox q;
      for (int k = 0; k < 3; ++k) {
        double step = step_of(f.biased_exp[std::size_t(k)]);
        auto nearest = [&](double x) { return std::uint8_t(std::clamp(std::round((x - f.origin[std::size_t(k)]) / step), 0.0, 255.0)); };
        q.lo[std::size_t(k)] = nearest(b.lo[k]);
        q.hi[std::size_t(k)] = nearest(b.hi[k]);
      }
      check_contains(f, q, b, v, "nearest");
    }
  }
  EXPECT_GT(v.count, 100);
}

TEST(QuantNode, FrameCoversTheNodeWithTheSmallestStep) {
  for (double extent : {0.0, 1e-30, 1.0, 255.0, 256.0, 1e20, 6e38}) {
    Aabb node;
    node.lo = glm::dvec3(-extent / 2);
    node.hi = glm::dvec3(extent / 2);
    QuantFrame f = quant_frame(node);
    for (int k = 0; k < 3; ++k) {
      int e = f.biased_exp[std::size_t(k)];
      EXPECT_GE(double(quant_decode(f.origin[std::size_t(k)], e, 255)), node.hi[k]) << extent;
      if (e > 1) {
        EXPECT_LT(double(quant_decode(f.origin[std::size_t(k)], e - 1, 255)), node.hi[k]) << extent;
      }
    }
  }
}

bool contains(const Aabb& outer, const Aabb& inner) {
  for (int k = 0; k < 3; ++k)
    if (!(outer.lo[k] <= inner.lo[k] && outer.hi[k] >= inner.hi[k])) return false;
  return true;
}

// Walks one BLAS through node_slots (the kernels' decode): each primitive once, and
// inside the box of its leaf slot and of every inner slot above it, each box in its
// node's frame (o4), where the primitive's extent along the frame's rows is exact in
// double. (q8 boxes need not nest: a node's children are quantised in its own frame,
// the node's slot in its parent's; both enclose the exact boxes, which is what the
// traversal relies on.)
// support(prim, dir): the primitive's greatest extent along dir.
using Support = std::function<double(int, const glm::dvec3&)>;
void check_blas(const PackedScene& ps, int root, std::size_t prims, const Support& support) {
  std::vector<int> seen(prims, 0);
  int misses = 0;
  std::vector<NodeSlot> above;
  std::function<void(int)> walk = [&](int node) {
    for (const NodeSlot& s : node_slots(ps, node)) {
      if (s.count < 0) continue;
      above.push_back(s);
      if (s.count == 0) walk(s.child);
      for (int j = 0; j < s.count; ++j) {
        int prim = ps.refs.at(std::size_t(s.child + j));
        ++seen.at(std::size_t(prim));
        for (const NodeSlot& a : above) {
          Aabb b;
          for (int k = 0; k < 3; ++k) {
            const glm::dvec3 m = a.frame.row(k);
            b.lo[k] = -support(prim, -m);
            b.hi[k] = support(prim, m);
          }
          misses += !contains(a.box, b);
        }
      }
      above.pop_back();
    }
  };
  walk(root);
  EXPECT_EQ(misses, 0) << "slot boxes that miss a primitive below them";
  EXPECT_TRUE(std::all_of(seen.begin(), seen.end(), [](int k) { return k == 1; }));
}

class EveryFormat : public ::testing::TestWithParam<NodeFormat> {};

TEST_P(EveryFormat, EveryPrimitiveOnceInsideItsBoxes) {
  Scene s;
  s.geometries.push_back(make_random_capsules(5000, 0.001f, 0.02f, 1.0, 7));
  s.instances.push_back({0, {}});
  AccelOptions opt;
  opt.nodes = GetParam();
  PackedScene ps = build_accel(s, Method::Ref, opt);
  EXPECT_EQ(ps.features.nodes, GetParam());
  EXPECT_EQ(ps.stats.node_bytes, ps.node_count() * node_format_bytes(GetParam()));
  EXPECT_EQ(ps.stats.node_bytes, ps.node_bytes());
  std::vector<BallHull> hulls;
  for (std::size_t p = 0; p < s.geometries[0].capsules.size(); ++p) hulls.push_back(ball_hull(s.geometries[0], p));
  // the BLAS is appended first, its root at 0
  check_blas(ps, 0, hulls.size(), [&](int p, const glm::dvec3& d) { return hulls[std::size_t(p)].support(d); });
  // o4 must rotate some nodes of long thin capsules, or the format is not exercised.
  if (GetParam() == NodeFormat::O4) {
    EXPECT_GT(ps.stats.oriented_nodes, ps.stats.blas_nodes / 20);
  }
}

// The deepest stack the kernels' discipline reaches on this tree (all inner children
// pushed, the one popped first chosen adversarially: the one whose subtree needs most),
// found by an explicit-stack walk over the decoded slots.
int simulated_stack(const PackedScene& ps, int root) {
  std::function<int(int)> need = [&](int node) {
    int inner = 0, deepest = 0;
    for (const NodeSlot& s : node_slots(ps, node))
      if (s.count == 0) {
        ++inner;
        deepest = std::max(deepest, need(s.child));
      }
    return inner == 0 ? 0 : inner - 1 + std::max(1, deepest);
  };
  std::vector<int> stack{root};
  int worst = 1;
  while (!stack.empty()) {
    int node = stack.back();
    stack.pop_back();
    std::vector<std::pair<int, int>> kids; // (need, child)
    for (const NodeSlot& s : node_slots(ps, node))
      if (s.count == 0) kids.push_back({need(s.child), s.child});
    std::sort(kids.begin(), kids.end()); // the neediest is pushed last, popped first
    for (const auto& k : kids) stack.push_back(k.second);
    worst = std::max(worst, int(stack.size()));
  }
  return worst;
}

// The deepest stack the kernels reach (kernels/traverse.h: the nearest inner child is
// held for the next visit, the others pushed; children that are leaves never pushed),
// with the neediest child taken as the nearest: an explicit walk over the decoded slots.
int simulated_kernel_stack(const PackedScene& ps, int root) {
  std::function<int(int)> need = [&](int node) {
    int inner = 0, deepest = 0;
    for (const NodeSlot& s : node_slots(ps, node))
      if (s.count == 0) {
        ++inner;
        deepest = std::max(deepest, need(s.child));
      }
    return inner == 0 ? 0 : inner - 1 + deepest;
  };
  std::vector<int> stack;
  int node = root, worst = 0;
  bool held = true;
  while (held || !stack.empty()) {
    if (!held) {
      node = stack.back();
      stack.pop_back();
    }
    held = false;
    std::vector<std::pair<int, int>> kids; // (need, child), the neediest last: held
    for (const NodeSlot& s : node_slots(ps, node))
      if (s.count == 0) kids.push_back({need(s.child), s.child});
    std::sort(kids.begin(), kids.end());
    for (const auto& k : kids) {
      if (held) stack.push_back(node);
      node = k.second;
      held = true;
    }
    worst = std::max(worst, int(stack.size()));
  }
  return worst;
}

BinaryBvh random_tree(int n, double octaves, std::uint64_t seed, std::vector<std::int32_t>& ids) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<Aabb> boxes;
  for (int i = 0; i < n; ++i) {
    double scale = std::pow(2.0, -octaves * u(rng));
    glm::dvec3 c = glm::dvec3(u(rng), u(rng), u(rng)) * scale;
    boxes.push_back({c - scale * 1e-3, c + scale * 1e-3});
  }
  ids.resize(boxes.size());
  for (std::size_t i = 0; i < ids.size(); ++i) ids[i] = std::int32_t(i);
  return build_binned_sah(boxes);
}

TEST_P(EveryFormat, StackBoundHoldsAndIsReached) {
  // Uniform boxes (a balanced tree: wide nodes full) and boxes whose sizes and
  // positions span 12 octaves (a deeper, lopsided tree).
  for (double octaves : {0.0, 12.0}) {
    std::vector<std::int32_t> ids;
    BinaryBvh bvh = random_tree(60000, octaves, 5, ids);
    PackedScene ps;
    ps.features.nodes = GetParam();
    WideBvhInfo info = append_bvh_nodes(bvh, ids, GetParam(), ps);
    int simulated = simulated_stack(ps, info.root);
    // The bound counts the root's entry, which is popped before anything is pushed.
    EXPECT_LE(simulated, info.stack_need) << octaves;
    EXPECT_GE(simulated, info.stack_need - 1) << octaves;
    EXPECT_LE(info.stack_need, MASQ_STACK_MAX);
    // What the kernels' stacks are sized from (KernelFeatures::tlas_stack, blas_stack)
    // is exactly what their walk reaches.
    EXPECT_EQ(simulated_kernel_stack(ps, info.root), info.kernel_stack) << octaves;
    EXPECT_LT(info.kernel_stack, info.stack_need) << octaves;
    EXPECT_EQ(ps.refs.size(), ids.size());
  }
}

// A tree collapsed on its own and placed later (the cluster BLAS: collapsed on all
// threads, appended in order) is the bytes append_bvh_nodes appends at the same ends:
// three trees, the later two placed after the nodes and references already there, in
// the reverse of their order (as threads may place them).
TEST_P(EveryFormat, CollapsedTreesPlacedLaterAreTheAppendedBytes) {
  std::vector<std::vector<std::int32_t>> ids(3);
  std::vector<BinaryBvh> trees;
  for (int t = 0; t < 3; ++t) trees.push_back(random_tree(500 + 700 * t, 6.0, 11 + t, ids[std::size_t(t)]));
  PackedScene appended, placed;
  appended.features.nodes = placed.features.nodes = GetParam();
  std::vector<WideBvhInfo> want;
  std::vector<CollapsedBvh> collapsed;
  for (std::size_t t = 0; t < 3; ++t) {
    want.push_back(append_bvh_nodes(trees[t], ids[t], GetParam(), appended));
    collapsed.push_back(collapse_bvh(trees[t], ids[t], GetParam()));
  }
  grow_node_arrays(placed, collapsed_nodes(collapsed[0]), collapsed[0].refs.size());
  EXPECT_EQ(place_collapsed(collapsed[0], placed, 0, 0).root, want[0].root);
  const std::size_t node_at = placed.node_count(), ref_at = placed.refs.size();
  const std::size_t nodes1 = collapsed_nodes(collapsed[1]), refs1 = collapsed[1].refs.size();
  grow_node_arrays(placed, nodes1 + collapsed_nodes(collapsed[2]), refs1 + collapsed[2].refs.size());
  const WideBvhInfo second_last = place_collapsed(collapsed[2], placed, node_at + nodes1, ref_at + refs1);
  const WideBvhInfo first = place_collapsed(collapsed[1], placed, node_at, ref_at);
  EXPECT_EQ(first.root, want[1].root);
  EXPECT_EQ(second_last.root, want[2].root);
  EXPECT_EQ(first.nodes, want[1].nodes);
  EXPECT_EQ(second_last.sah_cost, want[2].sah_cost);
  EXPECT_EQ(placed.node_bytes(), appended.node_bytes());
  EXPECT_EQ(placed.refs, appended.refs);
  auto bytes_equal = [](const auto& a, const auto& b) {
    return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(a[0])) == 0;
  };
  EXPECT_TRUE(bytes_equal(placed.nodes, appended.nodes));
  EXPECT_TRUE(bytes_equal(placed.nodes8, appended.nodes8));
  EXPECT_TRUE(bytes_equal(placed.qnodes, appended.qnodes));
  EXPECT_TRUE(bytes_equal(placed.onodes, appended.onodes));
  // Into a scene of another node format: refused.
  PackedScene other;
  other.features.nodes = GetParam() == NodeFormat::W4 ? NodeFormat::W8 : NodeFormat::W4;
  EXPECT_THROW(place_collapsed(collapsed[0], other, 0, 0), Error);
}

TEST_P(EveryFormat, DeepTreesGetFewerInnerChildrenPerNode) {
  // Sizes over 40 octaves: full nodes would need more than the kernels' stack (w4: 119,
  // w8: 241 entries), so the collapse caps the inner children per node.
  std::vector<std::int32_t> ids;
  BinaryBvh bvh = random_tree(60000, 40.0, 5, ids);
  PackedScene ps;
  ps.features.nodes = GetParam();
  WideBvhInfo info = append_bvh_nodes(bvh, ids, GetParam(), ps);
  EXPECT_LT(info.max_inner, (GetParam() == NodeFormat::W4 || GetParam() == NodeFormat::O4) ? 4 : 8);
  EXPECT_LE(simulated_stack(ps, info.root), info.stack_need);
  EXPECT_LE(info.stack_need, MASQ_STACK_MAX);
  EXPECT_EQ(simulated_kernel_stack(ps, info.root), info.kernel_stack);
  EXPECT_EQ(ps.refs.size(), ids.size());
  std::vector<Aabb> boxes(ids.size());
  for (const BinaryNode& n : bvh.nodes)
    for (int i = n.first; i < n.first + n.count; ++i) boxes[std::size_t(bvh.order[std::size_t(i)])] = n.box;
  check_blas(ps, info.root, boxes.size(), [&](int p, const glm::dvec3& d) {
    const Aabb& b = boxes[std::size_t(p)];
    return std::max(d.x * b.lo.x, d.x * b.hi.x) + std::max(d.y * b.lo.y, d.y * b.hi.y) +
           std::max(d.z * b.lo.z, d.z * b.hi.z);
  });
}

// A path of 200 nodes, each with a second inner child: no collapse fits 64 entries.
TEST_P(EveryFormat, TreesNoCollapseFitsAreRejected) {
  BinaryBvh bvh;
  Aabb unit;
  unit.lo = glm::dvec3(0.0);
  unit.hi = glm::dvec3(1.0);
  auto leaf = [&]() {
    bvh.nodes.push_back({unit, -1, -1, int(bvh.order.size()), 1});
    bvh.order.push_back(int(bvh.order.size()));
    return int(bvh.nodes.size()) - 1;
  };
  auto inner = [&](int l, int r) {
    bvh.nodes.push_back({unit, l, r, 0, 0});
    return int(bvh.nodes.size()) - 1;
  };
  // Built bottom-up, then the root moved to index 0.
  int path = inner(leaf(), leaf());
  for (int i = 0; i < 200; ++i) {
    int side = inner(inner(leaf(), leaf()), inner(leaf(), leaf()));
    path = inner(path, side);
  }
  std::swap(bvh.nodes[0], bvh.nodes[std::size_t(path)]);
  for (BinaryNode& n : bvh.nodes) {
    if (n.left == 0) n.left = path;
    else if (n.left == path) n.left = 0;
    if (n.right == 0) n.right = path;
    else if (n.right == path) n.right = 0;
  }
  std::vector<std::int32_t> ids(bvh.order.size());
  for (std::size_t i = 0; i < ids.size(); ++i) ids[i] = std::int32_t(i);
  PackedScene ps;
  ps.features.nodes = GetParam();
  try {
    append_bvh_nodes(bvh, ids, GetParam(), ps);
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("stack"), std::string::npos) << e.what();
  }
}

INSTANTIATE_TEST_SUITE_P(Formats, EveryFormat, ::testing::ValuesIn(node_format_table.values()),
                         [](const ::testing::TestParamInfo<NodeFormat>& i) { return node_format_name(i.param); });

TEST(NodeFormats, EightWideNodesHoldUpToEightChildren) {
  Scene s;
  s.geometries.push_back(make_random_capsules(20000, 0.001f, 0.02f, 1.0, 9));
  s.instances.push_back({0, {}});
  AccelOptions o4, o8;
  o8.nodes = NodeFormat::W8;
  PackedScene w4 = build_accel(s, Method::Ref, o4), w8 = build_accel(s, Method::Ref, o8);
  int most = 0;
  for (std::size_t n = 0; n < w8.node_count(); ++n) {
    int used = 0;
    for (const NodeSlot& slot : node_slots(w8, int(n))) used += slot.count >= 0;
    most = std::max(most, used);
  }
  EXPECT_EQ(most, 8);
  EXPECT_LT(w8.stats.blas_nodes * 4, w4.stats.blas_nodes * 3); // fewer, fuller nodes
  EXPECT_LT(w8.stats.max_depth, w4.stats.max_depth);
}

// The framer offers each o4 node its parent's frame (NodeFramer::choose, kFrameReuse),
// so that the cpu walk reuses the ray it already rotated (O4RayCache): over the default
// bundle's nearly parallel strands most rotated nodes under a rotated parent keep its
// nine bytes (167 of 169; 91 when each takes its own best candidate). The bundle of
// 8,000 strands also has nodes over enough references for the framer to plan sibling
// subtrees at once (bvh/nodes/wide_bvh.cpp, plan_frames): those must hand each child
// its parent's frame too.
class O4ParentFrames : public ::testing::TestWithParam<int> {};
TEST_P(O4ParentFrames, NodesOverParallelStrandsKeepTheirParentsFrame) {
  BundleParams bp;
  bp.count = GetParam();
  Scene s;
  s.geometries.push_back(make_bundle(bp));
  s.instances.push_back({0, {}});
  AccelOptions opt;
  opt.nodes = NodeFormat::O4;
  PackedScene ps = build_accel(s, Method::Ref, opt);
  int pairs = 0, kept = 0;
  for (std::size_t n = 0; n < ps.node_count(); ++n) {
    const NodeSlots slots = node_slots(ps, int(n));
    if (slots.begin() == slots.end() || !slots.begin()->frame.oriented) continue;
    for (const NodeSlot& slot : slots) {
      if (slot.count != 0) continue;
      const NodeSlots below = node_slots(ps, slot.child);
      if (below.begin() == below.end() || !below.begin()->frame.oriented) continue;
      ++pairs;
      kept += below.begin()->frame.q == slots.begin()->frame.q;
    }
  }
  EXPECT_GT(pairs, 50);
  EXPECT_GT(kept * 4, pairs * 3) << kept << " of " << pairs << " rotated children keep the parent's frame";
}
INSTANTIATE_TEST_SUITE_P(NodeFormats, O4ParentFrames, ::testing::Values(1000, 8000));

TEST(NodeFormats, NamesParseAndBadOnesAreRejected) {
  for (NodeFormat f : node_format_table.values()) EXPECT_EQ(parse_node_format(node_format_name(f)), f);
  EXPECT_THROW(parse_node_format("w16"), Error);
  EXPECT_EQ(node_format_bytes(NodeFormat::W4), 128u);
  EXPECT_EQ(node_format_bytes(NodeFormat::W8), 256u);
  EXPECT_EQ(node_format_bytes(NodeFormat::Q8), 80u);
  EXPECT_EQ(node_format_bytes(NodeFormat::O4), 144u);
}

} // namespace
