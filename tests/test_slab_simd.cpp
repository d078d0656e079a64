// The cpu dialect's vectorised node tests (kernels/slab_simd_cpp.h) against the one-source
// loops that GLSL and OpenCL run: every entry distance, exit distance, child and count
// must be bit-identical, for w4 nodes (plain and padded) and w8 nodes, including rays
// parallel to a slab, origins on a plane, flat boxes, empty slots holding garbage and
// ray intervals that end inside a box. Equal bits are what keep the backends' hits
// identical (tests/test_cross_backend.cpp).
#include "kernels/node_formats.h"
#include "kernels/traverse.h"
#include <gtest/gtest.h>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <string>
#include <vector>

using namespace masq::kernel;
using masq::kernel::v_default::hits_w8;
using masq::kernel::v_default::hits_q8;
using masq::kernel::v_default::hits_q8_loop;
using masq::kernel::v_default::hits_w8_loop;
using masq::kernel::v_default::intersect_wide_node;
using masq::kernel::v_default::intersect_wide_node_loop;
using masq::kernel::v_default::intersect_wide_node_padded;
using masq::kernel::v_default::intersect_wide_node_padded_loop;
using masq::kernel::v_default::safe_rcp3;
using masq::kernel::v_default::WideHits;

namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

struct Slot {
  float lo[3], hi[3];
  int child, count;
};

// A random slot at scale s: ordinary boxes, flat boxes, points, and empty slots whose
// planes hold whatever garbage (NaN, inf, reversed bounds) a node may carry there.
Slot random_slot(std::mt19937& rng, float s) {
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  std::uniform_int_distribution<int> kind(0, 9);
  Slot sl{};
  int k = kind(rng);
  for (int a = 0; a < 3; ++a) {
    float c = s * u(rng), e = s * 0.5f * (u(rng) + 1.0f);
    sl.lo[a] = c - e;
    sl.hi[a] = c + e;
    if (k == 1 && a == 1) sl.hi[a] = sl.lo[a];         // flat
    if (k == 2) sl.hi[a] = sl.lo[a];                   // point
  }
  sl.child = int(rng() % 1000);
  sl.count = k == 3 ? 0 : int(rng() % 5);
  if (k >= 8) { // empty
    sl.count = -1;
    const float junk[] = {std::nanf(""), kInf, -kInf, 1e30f};
    for (int a = 0; a < 3; ++a) {
      sl.lo[a] = junk[rng() % 4];
      sl.hi[a] = -junk[rng() % 4];
    }
  }
  return sl;
}

struct TestRay {
  vec3 o, inv_d;
  float tmin, tmax;
  vec3 pad;
};

// Random rays at scale s; some start on a plane of slot 0, some run parallel to an axis
// (safe_rcp's 1e30), some end or start inside the boxes.
TestRay random_ray(std::mt19937& rng, float s, const Slot& first) {
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  TestRay r;
  r.o = vec3(2.0f * s * u(rng), 2.0f * s * u(rng), 2.0f * s * u(rng));
  vec3 d(u(rng), u(rng), u(rng));
  // Half the rays aim at the first slot's box, so hits are as common as misses.
  if (u(rng) < 0.0f && first.count >= 0)
    for (int a = 0; a < 3; ++a) d[a] = 0.5f * (first.lo[a] + first.hi[a]) - r.o[a];
  int k = int(rng() % 6);
  if (k == 0) d[int(rng() % 3)] = 0.0f;
  if (k == 1 && first.count >= 0) r.o[int(rng() % 3)] = first.lo[rng() % 3];
  if (k == 2) d = vec3(0.0f, 0.0f, u(rng) < 0.0f ? -1.0f : 1.0f);
  r.inv_d = safe_rcp3(d);
  r.tmin = k == 3 ? s * 0.5f * (u(rng) + 1.0f) : 0.0f;
  r.tmax = k == 4 ? s * (u(rng) + 1.0f) : kInf;
  r.pad = vec3(s * 1e-4f * (u(rng) + 1.0f), 0.0f, s * 1e-3f * (u(rng) + 1.0f));
  return r;
}

std::uint32_t bits(float x) { return std::bit_cast<std::uint32_t>(x); }

struct Tally {
  long hits = 0, misses = 0, mismatches = 0;
  std::string first;
};

void compare(const WideHits& got, const WideHits& want, int width, const Slot* slots, Tally& t,
             const std::string& what) {
  for (int i = 0; i < width; ++i) {
    bool live = slots[i].count >= 0;
    bool same = bits(got.tnear[i]) == bits(want.tnear[i]) && got.child[i] == want.child[i] &&
                got.count[i] == want.count[i] && (!live || bits(got.tfar[i]) == bits(want.tfar[i]));
    (want.tnear[i] == kInf ? t.misses : t.hits)++;
    if (!same && t.mismatches++ == 0)
      t.first = what + " slot " + std::to_string(i) + ": tnear " + std::to_string(got.tnear[i]) + " vs " +
                std::to_string(want.tnear[i]) + ", tfar " + std::to_string(got.tfar[i]) + " vs " +
                std::to_string(want.tfar[i]);
  }
}

WideNode w4_node(const Slot* s) {
  WideNode n{};
  for (int i = 0; i < 4; ++i) {
    n.lo_x[i] = s[i].lo[0];
    n.hi_x[i] = s[i].hi[0];
    n.lo_y[i] = s[i].lo[1];
    n.hi_y[i] = s[i].hi[1];
    n.lo_z[i] = s[i].lo[2];
    n.hi_z[i] = s[i].hi[2];
    n.child[i] = s[i].child;
    n.count[i] = s[i].count;
  }
  return n;
}

std::vector<uint> w8_words(const Slot* s) {
  std::vector<uint> w(MASQ_W8_WORDS);
  for (int i = 0; i < 8; ++i) {
    w[MASQ_W8_LO_X + i] = bits(s[i].lo[0]);
    w[MASQ_W8_HI_X + i] = bits(s[i].hi[0]);
    w[MASQ_W8_LO_Y + i] = bits(s[i].lo[1]);
    w[MASQ_W8_HI_Y + i] = bits(s[i].hi[1]);
    w[MASQ_W8_LO_Z + i] = bits(s[i].lo[2]);
    w[MASQ_W8_HI_Z + i] = bits(s[i].hi[2]);
    w[MASQ_W8_CHILD + i] = std::bit_cast<uint>(s[i].child);
    w[MASQ_W8_COUNT + i] = std::bit_cast<uint>(s[i].count);
  }
  return w;
}

// An 8-wide format's cpu test against its loop on one node, plain and padded.
typedef WideHits (*NodeTest)(const KernelData&, int, vec3, vec3, int, vec3, float, float);
void compare_eight_wide(NodeTest simd_test, NodeTest loop_test, const KernelData& kd, const TestRay& r,
                        const Slot* sl, Tally& plain, Tally& padded, const std::string& name) {
  compare(simd_test(kd, 0, r.o, r.inv_d, 0, r.pad, r.tmin, r.tmax),
          loop_test(kd, 0, r.o, r.inv_d, 0, r.pad, r.tmin, r.tmax), 8, sl, plain, name);
  compare(simd_test(kd, 0, r.o, r.inv_d, 1, r.pad, r.tmin, r.tmax),
          loop_test(kd, 0, r.o, r.inv_d, 1, r.pad, r.tmin, r.tmax), 8, sl, padded, name + " padded");
}

// Hits and misses both common (each at least 5% of the slot tests): not vacuous.
void expect_clean(const Tally& t) {
  EXPECT_EQ(t.mismatches, 0) << t.first;
  EXPECT_GT(t.hits, (t.hits + t.misses) / 20);
  EXPECT_GT(t.misses, (t.hits + t.misses) / 20);
}

} // namespace

TEST(SlabSimd, FourWideMatchesTheLoopBitForBit) {
  std::mt19937 rng(7);
  Tally plain, padded;
  for (float s : {1e-3f, 1.0f, 250.0f, 3e4f})
    for (int c = 0; c < 40000; ++c) {
      Slot sl[4];
      for (Slot& x : sl) x = random_slot(rng, s);
      WideNode n = w4_node(sl);
      TestRay r = random_ray(rng, s, sl[0]);
      compare(intersect_wide_node(n, r.o, r.inv_d, r.tmin, r.tmax),
              intersect_wide_node_loop(n, r.o, r.inv_d, r.tmin, r.tmax), 4, sl, plain, "w4");
      compare(intersect_wide_node_padded(n, r.o, r.inv_d, r.pad, r.tmin, r.tmax),
              intersect_wide_node_padded_loop(n, r.o, r.inv_d, r.pad, r.tmin, r.tmax), 4, sl, padded, "w4 padded");
    }
  expect_clean(plain);
  expect_clean(padded);
}

TEST(SlabSimd, EightWideMatchesTheLoopBitForBit) {
  std::mt19937 rng(11);
  Tally plain, padded;
  KernelData kd{};
  for (float s : {1e-3f, 1.0f, 250.0f, 3e4f})
    for (int c = 0; c < 20000; ++c) {
      Slot sl[8];
      for (Slot& x : sl) x = random_slot(rng, s);
      std::vector<uint> words = w8_words(sl);
      kd.node_words = words.data();
      TestRay r = random_ray(rng, s, sl[0]);
      compare_eight_wide(hits_w8, hits_w8_loop, kd, r, sl, plain, padded, "w8");
    }
  expect_clean(plain);
  expect_clean(padded);
}

// q8: random grid bytes, exponents and slot kinds (empty, inner, leaves of 1..127) over
// a random origin; the decoded planes and the children's running indices must agree.
TEST(SlabSimd, QuantisedEightWideMatchesTheLoopBitForBit) {
  std::mt19937 rng(13);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  Tally plain, padded;
  KernelData kd{};
  std::vector<uint> w(MASQ_Q8_WORDS);
  for (float s : {1e-3f, 1.0f, 250.0f, 3e4f})
    for (int c = 0; c < 20000; ++c) {
      for (uint& x : w) x = uint(rng());
      for (int a = 0; a < 3; ++a) w[MASQ_Q8_ORIGIN + a] = bits(s * u(rng));
      // exponent of the grid step: about s / 256, so boxes land near the origin
      int e = 127 + int(std::floor(std::log2(s))) - 8 + int(rng() % 3);
      w[MASQ_Q8_EXPS] = uint(e) | uint(e) << 8 | uint(e) << 16;
      w[MASQ_Q8_CHILD_BASE] = rng() % 1000;
      w[MASQ_Q8_REF_BASE] = rng() % 1000;
      Slot sl[8];
      w[MASQ_Q8_META] = w[MASQ_Q8_META + 1] = 0;
      for (int i = 0; i < 8; ++i) {
        int k = int(rng() % 4);
        uint m = k == 0 ? 0u : k == 1 ? MASQ_Q8_INNER : 1u + uint(rng() % 127);
        w[MASQ_Q8_META + i / 4] |= m << (8 * (i % 4));
        sl[i].count = m == 0u ? -1 : 0;
        // the box the bytes make: decoded hi >= lo on every axis, as the host writes them
        for (int a = 0; a < 3; ++a) {
          int lo_word = MASQ_Q8_QLO_X + 4 * a + i / 4, hi_word = lo_word + 2, sh = 8 * (i % 4);
          uint ql = (w[std::size_t(lo_word)] >> sh) & 255u, qh = (w[std::size_t(hi_word)] >> sh) & 255u;
          if (qh < ql) {
            w[std::size_t(lo_word)] = (w[std::size_t(lo_word)] & ~(255u << sh)) | qh << sh;
            w[std::size_t(hi_word)] = (w[std::size_t(hi_word)] & ~(255u << sh)) | ql << sh;
            std::swap(ql, qh);
          }
          float origin = std::bit_cast<float>(w[std::size_t(MASQ_Q8_ORIGIN + a)]), step = std::ldexp(1.0f, e - 127);
          sl[i].lo[a] = origin + float(ql) * step; // where the test aims, not a reference
          sl[i].hi[a] = origin + float(qh) * step;
        }
      }
      kd.node_words = w.data();
      Slot aim = sl[rng() % 8];
      aim.count = 0;
      TestRay r = random_ray(rng, s, aim);
      compare_eight_wide(hits_q8, hits_q8_loop, kd, r, sl, plain, padded, "q8");
    }
  expect_clean(plain);
  expect_clean(padded);
}

// The comparison itself would notice a vector test that differs in the last bit.
TEST(SlabSimd, AOneUlpChangeWouldBeCaught) {
  Slot sl[4];
  for (int i = 0; i < 4; ++i) sl[i] = Slot{{-1.0f, -1.0f, -1.0f}, {1.0f, 1.0f, 1.0f}, i, 1};
  WideNode n = w4_node(sl);
  vec3 o(-5.0f, 0.1f, 0.2f), inv_d = safe_rcp3(vec3(1.0f, 0.01f, 0.02f));
  WideHits want = intersect_wide_node_loop(n, o, inv_d, 0.0f, kInf);
  WideHits got = intersect_wide_node(n, o, inv_d, 0.0f, kInf);
  Tally same;
  compare(got, want, 4, sl, same, "same");
  EXPECT_EQ(same.mismatches, 0) << same.first;
  EXPECT_EQ(same.misses, 0);
  got.tnear[2] = std::nextafter(got.tnear[2], kInf);
  Tally off;
  compare(got, want, 4, sl, off, "off");
  EXPECT_EQ(off.mismatches, 1);
}

// The cpu traversal takes a node's hit leaves and hit inner children from
// simd::slot_masks and simd::sorted_slots, and the TLAS walk its hit children from the
// C++ order_children; each must come in the order the one-source loops take them from
// the insertion sort (entry distance, ties in slot order).
TEST(SlabSimd, SortedSlotsKeepOrderChildrensOrder) {
  std::mt19937 rng(11);
  std::uniform_int_distribution<int> pick_t(0, 4), pick_count(-1, 3);
  int ties = 0, visits = 0;
  for (int width : {4, 8})
    for (int trial = 0; trial < 40000; ++trial) {
      WideHits wh{};
      for (int i = 0; i < width; ++i) {
        int k = pick_t(rng); // few distinct distances: ties are common
        wh.count[i] = pick_count(rng);
        wh.tnear[i] = k == 4 || wh.count[i] < 0 ? kInf : 0.5f * float(k);
      }
      // The one-source insertion sort (OpenCL's order) is the reference; the C++
      // order_children (bitmask and sorted_slots, the TLAS walk's) must match it too.
      masq::kernel::v_default::ChildOrder co = masq::kernel::v_default::order_children_loop(wh, width);
      masq::kernel::v_default::ChildOrder fast = masq::kernel::v_default::order_children(wh, width);
      ASSERT_EQ(std::vector<int>(fast.slot, fast.slot + fast.n), std::vector<int>(co.slot, co.slot + co.n))
          << "width " << width << " trial " << trial;
      std::vector<int> want_leaves, want_inner;
      for (int k = 0; k < co.n; ++k) {
        int i = co.slot[k];
        if (wh.count[i] > 0) want_leaves.push_back(i);
        if (wh.count[i] == 0) want_inner.push_back(i);
        for (int j = 0; j < k; ++j) ties += wh.tnear[co.slot[j]] == wh.tnear[i];
      }
      simd::SlotMasks m = simd::slot_masks(wh.tnear, wh.count, width);
      int slot[8];
      int n = simd::sorted_slots(wh.tnear, m.leaves, slot);
      ASSERT_EQ(std::vector<int>(slot, slot + n), want_leaves) << "width " << width << " trial " << trial;
      n = simd::sorted_slots(wh.tnear, m.inner, slot);
      ASSERT_EQ(std::vector<int>(slot, slot + n), want_inner) << "width " << width << " trial " << trial;
      visits += co.n;
    }
  EXPECT_GT(ties, visits / 10); // the stable order was tested, not only distinct keys
}

// Occlusion queries visit a node's hit children entered after tmin first, then those the
// ray starts in (entry clamped to tmin), each group in slot order (child_order.h). The
// reference is that rule written out; the one-source order_children_occlusion (OpenCL's
// and Vulkan's) and the cpu's bitmask form (simd::start_slots, simd::occlusion_slots)
// must both give it.
TEST(SlabSimd, OcclusionSlotsFollowTheOcclusionOrder) {
  std::mt19937 rng(12);
  std::uniform_int_distribution<int> pick_t(0, 4), pick_count(-1, 3);
  const float tmin = 0.5f;
  int starts = 0, after = 0;
  for (int width : {4, 8})
    for (int trial = 0; trial < 40000; ++trial) {
      WideHits wh{};
      for (int i = 0; i < 8; ++i) wh.tnear[i] = kInf, wh.count[i] = -1;
      for (int i = 0; i < width; ++i) {
        int k = pick_t(rng); // 0.5 is tmin: a box the ray starts in
        wh.count[i] = pick_count(rng);
        wh.tnear[i] = k == 4 || wh.count[i] < 0 ? kInf : 0.5f + 0.5f * float(k);
      }
      std::vector<int> want, want_leaves, want_inner;
      for (int pass = 0; pass < 2; ++pass)
        for (int i = 0; i < width; ++i)
          if (wh.tnear[i] != kInf && (wh.tnear[i] <= tmin) == (pass == 1)) want.push_back(i);
      for (int i : want) {
        if (wh.count[i] > 0) want_leaves.push_back(i);
        if (wh.count[i] == 0) want_inner.push_back(i);
        (wh.tnear[i] <= tmin ? starts : after) += 1;
      }
      masq::kernel::v_default::ChildOrder co =
          masq::kernel::v_default::order_children_occlusion(wh, width, tmin);
      ASSERT_EQ(std::vector<int>(co.slot, co.slot + co.n), want) << "width " << width << " trial " << trial;
      simd::SlotMasks m = simd::slot_masks(wh.tnear, wh.count, width);
      unsigned in = simd::start_slots(wh.tnear, tmin, width);
      int slot[8];
      int n = simd::occlusion_slots(m.leaves, in, slot);
      ASSERT_EQ(std::vector<int>(slot, slot + n), want_leaves) << "width " << width << " trial " << trial;
      n = simd::occlusion_slots(m.inner, in, slot);
      ASSERT_EQ(std::vector<int>(slot, slot + n), want_inner) << "width " << width << " trial " << trial;
    }
  EXPECT_GT(starts, 10000); // both groups were tested
  EXPECT_GT(after, 10000);
}
