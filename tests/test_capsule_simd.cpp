// The cpu dialect's four- and eight-lane capsule intersector (kernels/capsule_simd_cpp.h) against
// the one-source intersect_capsule: every lane's hit flag, t, normal and axial parameter
// must be bit-identical to the scalar call, for thin, long, short, zero-length and
// invalid capsules, grazing and end-on rays, rays from far away and from a capsule's
// own surface, and intervals that cut crossings off (the all-lanes-miss early exit
// must never drop a crossing the scalar call finds). Then whole leaves: intersect_leaf (lanes taken in
// reference order) and a node's hit leaves paired into eight lanes (capsule_leaves)
// against the scalar loops they replace on cpu, closest and any hit.
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
namespace k = masq::kernel::v_default;

namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();
std::uint32_t bits(float x) { return std::bit_cast<std::uint32_t>(x); }

// A capsule near the origin at scale s: random direction and length (0 included), thin
// to fat radii, and now and then a zero, negative or NaN radius.
Capsule random_capsule(std::mt19937& rng, float s) {
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  Capsule c{};
  glm::vec3 a(s * u(rng), s * u(rng), s * u(rng));
  glm::vec3 dir = glm::normalize(glm::vec3(u(rng), u(rng), u(rng)) + glm::vec3(1e-3f));
  float len = (rng() % 8 == 0) ? 0.0f : s * 2.0f * (u(rng) + 1.0f);
  glm::vec3 b = a + dir * len;
  for (int i = 0; i < 3; ++i) {
    c.a[i] = a[i];
    c.b[i] = b[i];
  }
  const float radii[] = {s * 1e-4f, s * 0.01f, s * 0.3f, s * 2.0f};
  c.radius = radii[rng() % 4];
  int odd = int(rng() % 40);
  if (odd == 0) c.radius = 0.0f;
  if (odd == 1) c.radius = -c.radius;
  if (odd == 2) c.radius = std::nanf("");
  return c;
}

struct Probe {
  glm::vec3 o, d;
  float tmin, tmax;
};

// Rays at a capsule: through a point near its surface (grazing or not), from a point on
// it (secondary rays), along its axis, with unit or scaled directions and cut intervals.
Probe random_probe(std::mt19937& rng, const Capsule& c, float s) {
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  glm::vec3 a(c.a[0], c.a[1], c.a[2]), b(c.b[0], c.b[1], c.b[2]);
  float w = 0.5f * (u(rng) + 1.0f);
  glm::vec3 on_axis = a + (b - a) * w;
  float r = std::isfinite(c.radius) ? std::fabs(c.radius) : s;
  glm::vec3 off = glm::normalize(glm::vec3(u(rng), u(rng), u(rng)) + glm::vec3(1e-3f));
  glm::vec3 target = on_axis + off * (r * (1.0f + 0.05f * u(rng)));
  Probe p;
  int k = int(rng() % 5);
  if (k == 0) { // from the surface outwards
    p.o = on_axis + off * r;
    p.d = glm::normalize(off + 0.5f * glm::vec3(u(rng), u(rng), u(rng)));
  } else if (k == 1) { // along the axis, end-on
    p.o = a - (b - a) * 2.0f - glm::vec3(s);
    p.d = (b - a) + glm::vec3(1e-4f * s);
  } else if (k == 2) { // from far away: ts and p carry rounding of the distance's size
    p.o = target + glm::normalize(glm::vec3(u(rng), u(rng), u(rng)) + glm::vec3(1e-3f)) * (2e4f * s);
    p.d = target - p.o;
  } else {
    p.o = target + glm::vec3(u(rng), u(rng), u(rng)) * (10.0f * s);
    p.d = target - p.o;
  }
  if (rng() % 3 == 0) p.d *= 37.5f;
  float len = glm::length(p.d);
  p.tmin = rng() % 4 == 0 ? 0.5f / (len > 0.0f ? len : 1.0f) : 0.0f;
  p.tmax = rng() % 4 == 0 ? std::fabs(u(rng)) * 2.0f : kInf;
  if (rng() % 50 == 0) p.tmax = p.tmin - 1.0f; // empty interval
  return p;
}

struct Tally {
  long hits = 0, misses = 0, mismatches = 0;
  std::string first;
};

template <int L>
void compare_lane(const simd::CapsuleHitsN<L>& c, int lane, const k::PrimHit& want, Tally& t, const std::string& what) {
  bool hit = c.hit[lane] != 0;
  bool same = hit == (want.hit != 0);
  if (same && hit)
    same = bits(c.t[lane]) == bits(want.t) && bits(c.nx[lane]) == bits(want.normal.x) &&
           bits(c.ny[lane]) == bits(want.normal.y) && bits(c.nz[lane]) == bits(want.normal.z) &&
           bits(c.u[lane]) == bits(want.u);
  (want.hit != 0 ? t.hits : t.misses)++;
  if (!same && t.mismatches++ == 0)
    t.first = what + " lane " + std::to_string(lane) + ": hit " + std::to_string(hit) + " t " +
              std::to_string(c.t[lane]) + " vs hit " + std::to_string(want.hit) + " t " + std::to_string(want.t);
}

// The cpu's row copy (host/cpu/leaf_capsules.h) of capsules in slot order, zero padded.
struct Rows {
  std::vector<float> rows;
  int stride = 0;
};
Rows capsule_rows(const std::vector<Capsule>& slots) {
  Rows r;
  r.stride = int((slots.size() + 4 + 3) / 4 * 4);
  r.rows.assign(std::size_t(7 * r.stride), 0.0f);
  for (std::size_t i = 0; i < slots.size(); ++i) {
    const Capsule& c = slots[i];
    const float v[7] = {c.a[0], c.a[1], c.a[2], c.b[0], c.b[1], c.b[2], c.radius};
    for (int k = 0; k < 7; ++k) r.rows[std::size_t(k * r.stride) + i] = v[k];
  }
  return r;
}

} // namespace

TEST(CapsuleSimd, EveryLaneMatchesTheScalarIntersectorBitForBit) {
  std::mt19937 rng(5);
  Tally tally;
  for (float s : {1e-3f, 1.0f, 300.0f})
    for (int c = 0; c < 30000; ++c) {
      Capsule caps[4];
      int n = 1 + int(rng() % 4);
      for (int i = 0; i < 4; ++i) caps[i] = random_capsule(rng, s);
      Probe p = random_probe(rng, caps[rng() % std::uint32_t(n)], s);
      simd::CapsuleHits4 got = simd::capsule_hits4(caps, n, p.o, p.d, p.tmin, p.tmax);
      for (int i = 0; i < n; ++i)
        compare_lane(got, i, k::intersect_capsule(caps[i], p.o, p.d, p.tmin, p.tmax), tally,
                     "scale " + std::to_string(s));
      // Eight lanes from the row copy: these four in lanes 0-3, four more in lanes 4-7
      // (m of them valid; the rest read the rows' neighbours and padding, masked off).
      std::vector<Capsule> slots(caps, caps + 4);
      int m = 1 + int(rng() % 4);
      for (int i = 0; i < 4; ++i) slots.push_back(random_capsule(rng, s));
      Rows rows = capsule_rows(slots);
      simd::I8 valid = simd::I8{0, 1, 2, 3, 0, 1, 2, 3} < simd::I8{n, n, n, n, m, m, m, m};
      simd::CapsuleHitsN<8> got8 = simd::capsule_hits<simd::F8, simd::I8>(
          simd::capsule_rows8(rows.rows.data(), rows.stride, 0, 4), valid, p.o, p.d, p.tmin, p.tmax);
      for (int i = 0; i < 8; ++i) {
        if ((i < 4 ? i < n : i - 4 < m) == false) {
          if (got8.hit[i] != 0 && tally.mismatches++ == 0) tally.first = "an invalid lane of eight reports a hit";
          continue;
        }
        compare_lane(got8, i, k::intersect_capsule(slots[std::size_t(i)], p.o, p.d, p.tmin, p.tmax), tally,
                     "eight lanes, scale " + std::to_string(s));
      }
    }
  EXPECT_EQ(tally.mismatches, 0) << tally.first;
  // Not vacuous: hits and misses both common.
  EXPECT_GT(tally.hits, (tally.hits + tally.misses) / 10);
  EXPECT_GT(tally.misses, (tally.hits + tally.misses) / 10);
}

// Secondary rays as a strand gives them: a chain of capsules sharing their ends, rays
// from on, just inside or just outside one capsule's surface (joints included), leaving
// it tangentially, at grazing angles either way, or steeply. The lanes that pass the
// sphere and axis-line tests are mostly the capsules the ray starts on or behind, whose
// crossings lie before the interval: the "behind the start" test drops them. Where it
// may not (a ray that starts inside a neighbour's end ball and leaves through it, a
// tangent ray, one a rounding error outside), every lane must still be the scalar call.
TEST(CapsuleSimd, RaysLeavingAStrandMatchTheScalarIntersectorBitForBit) {
  std::mt19937 rng(21);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  const float offsets[] = {-1e-2f, -1e-5f, 0.0f, 1e-7f, 1e-5f, 1e-3f, 1e-2f, 0.05f};
  const float angles[] = {-0.3f, -1e-3f, 0.0f, 1e-5f, 1e-3f, 1e-2f, 0.3f, 1.2f};
  Tally tally;
  for (float s : {1e-3f, 1.0f, 300.0f})
    for (int c = 0; c < 20000; ++c) {
      // Nine points, eight capsules, each bent off the last direction by up to ~35 degrees.
      std::vector<Capsule> strand(8);
      glm::vec3 p(s * u(rng), s * u(rng), s * u(rng));
      glm::vec3 dir = glm::normalize(glm::vec3(u(rng), u(rng), u(rng)) + glm::vec3(1e-3f));
      const float radii[] = {1e-4f, 1e-2f, 0.3f};
      float r = s * radii[rng() % 3];
      for (Capsule& k : strand) {
        dir = glm::normalize(dir + 0.6f * glm::vec3(u(rng), u(rng), u(rng)));
        glm::vec3 q = p + dir * (s * (0.5f + 0.5f * (u(rng) + 1.0f)));
        for (int i = 0; i < 3; ++i) {
          k.a[i] = p[i];
          k.b[i] = q[i];
        }
        k.radius = r;
        p = q;
      }
      const Capsule& own = strand[rng() % 8];
      glm::vec3 a(own.a[0], own.a[1], own.a[2]), b(own.b[0], own.b[1], own.b[2]);
      glm::vec3 axis = glm::normalize(b - a);
      float w = rng() % 4 == 0 ? float(rng() % 2) : 0.5f * (u(rng) + 1.0f); // a joint now and then
      glm::vec3 n = glm::normalize(glm::cross(axis, glm::vec3(u(rng), u(rng), u(rng)) + glm::vec3(1e-3f)));
      glm::vec3 tangent = glm::normalize(glm::cross(axis, n) * u(rng) + axis * u(rng) + glm::vec3(1e-4f) * n);
      tangent = glm::normalize(tangent - n * glm::dot(tangent, n));
      Probe pr;
      pr.o = a + (b - a) * w + n * (r * (1.0f + offsets[rng() % 8]));
      float th = angles[rng() % 8];
      pr.d = (tangent * std::cos(th) + n * std::sin(th)) * (rng() % 3 == 0 ? 37.5f : 1.0f);
      pr.tmin = rng() % 4 == 0 ? 1e-6f * s : 0.0f;
      pr.tmax = rng() % 4 == 0 ? s * (u(rng) + 1.0f) : kInf;
      Rows rows = capsule_rows(strand);
      simd::CapsuleHitsN<8> got8 = simd::capsule_hits<simd::F8, simd::I8>(
          simd::capsule_rows8(rows.rows.data(), rows.stride, 0, 4), simd::I8{} == 0, pr.o, pr.d, pr.tmin, pr.tmax);
      simd::CapsuleHits4 got4 = simd::capsule_hits4(strand.data() + 2, 4, pr.o, pr.d, pr.tmin, pr.tmax);
      for (int i = 0; i < 8; ++i) {
        k::PrimHit want = k::intersect_capsule(strand[std::size_t(i)], pr.o, pr.d, pr.tmin, pr.tmax);
        compare_lane(got8, i, want, tally, "strand, scale " + std::to_string(s));
        if (i >= 2 && i < 6) compare_lane(got4, i - 2, want, tally, "strand, four lanes, scale " + std::to_string(s));
      }
    }
  EXPECT_EQ(tally.mismatches, 0) << tally.first;
  // Not vacuous: rays that leave the strand through a neighbour (a hit) and rays that
  // leave it clean (every lane a miss) both common.
  EXPECT_GT(tally.hits, (tally.hits + tally.misses) / 50);
  EXPECT_GT(tally.misses, (tally.hits + tally.misses) / 2);
}

// A leaf of 1..9 capsules (groups of four and a rest) through intersect_leaf, which
// takes the lanes in reference order, against the one-source loop over the same refs.
TEST(CapsuleSimd, LeavesGiveTheLoopsNearestAndFirstHit) {
  std::mt19937 rng(9);
  long hits = 0, mismatches = 0;
  std::string first;
  for (int any = 0; any < 2; ++any) {
    k::MASQ_ANY_HIT = any != 0;
    for (int c = 0; c < 20000; ++c) {
      int n = 1 + int(rng() % 9);
      std::vector<Capsule> caps(std::size_t(n) + 3);
      for (Capsule& x : caps) x = random_capsule(rng, 1.0f);
      // The leaf's references: a shuffled selection of the array, as a BVH leaf holds.
      std::vector<int> refs(static_cast<std::size_t>(n));
      for (int j = 0; j < n; ++j) refs[std::size_t(j)] = int(rng() % caps.size());
      std::vector<Capsule> leaf(static_cast<std::size_t>(n)); // the cpu's leaf-ordered copy
      for (int j = 0; j < n; ++j) leaf[std::size_t(j)] = caps[std::size_t(refs[std::size_t(j)])];
      Rows rows = capsule_rows(leaf);
      KernelData kd{};
      kd.capsules = caps.data();
      kd.refs = refs.data();
      kd.leaf_capsule_rows = rows.rows.data();
      kd.leaf_capsule_stride = rows.stride;
      Geometry g{MASQ_PRIM_CAPSULE, 0, int(caps.size()), 0};
      Probe p = random_probe(rng, caps[std::size_t(refs[0])], 1.0f);
      k::Nearest start = k::nearest_none(p.tmax);
      k::LeafOut got = k::intersect_leaf(kd, g, 0, n, 2, 3, p.o, p.d, p.tmin, start);
      // The loop the cpu no longer runs for capsules.
      k::Nearest want = start;
      for (int j = 0; j < n; ++j) {
        int prim = refs[std::size_t(j)];
        k::PrimHit ph = k::intersect_capsule(caps[std::size_t(prim)], p.o, p.d, p.tmin, want.t);
        want = k::nearest_take(want, ph, prim, 2, 3);
        if (any && want.prim >= 0) break;
      }
      bool same = got.nearest.prim == want.prim && bits(got.nearest.t) == bits(want.t) &&
                  got.nearest.geom == want.geom && got.nearest.inst == want.inst &&
                  bits(got.nearest.normal.x) == bits(want.normal.x) && bits(got.nearest.u) == bits(want.u);
      hits += want.prim >= 0;
      if (!same && mismatches++ == 0)
        first = "leaf of " + std::to_string(n) + (any ? " (any hit)" : "") + ": prim " +
                std::to_string(got.nearest.prim) + " t " + std::to_string(got.nearest.t) + " vs prim " +
                std::to_string(want.prim) + " t " + std::to_string(want.t);
    }
  }
  k::MASQ_ANY_HIT = false;
  EXPECT_EQ(mismatches, 0) << first;
  EXPECT_GT(hits, 40000 / 5);
}

// A node's hit leaves (1..8 leaves of 1..9 capsules, nearest entry first, some entered
// beyond a hit the ray already has) through capsule_leaves, which pairs leaves of up to
// four into eight lanes, against the one-source leaves loop: the same nearest hit (or
// first hit) and the same count of intersector calls.
TEST(CapsuleSimd, PairedLeavesGiveTheLoopsNearestAndFirstHit) {
  std::mt19937 rng(13);
  std::uniform_real_distribution<float> u01(0.0f, 1.0f);
  long hits = 0, pairs = 0, mismatches = 0;
  std::string first;
  for (int any = 0; any < 2; ++any) {
    k::MASQ_ANY_HIT = any != 0;
    k::MASQ_STATS = true;
    for (int c = 0; c < 20000; ++c) {
      std::vector<Capsule> caps(24);
      for (Capsule& x : caps) x = random_capsule(rng, 1.0f);
      int leaves = 1 + int(rng() % 8);
      k::WideHits wh = k::wide_hits_none();
      std::vector<int> refs;
      int slot[8];
      float t = 0.0f;
      for (int i = 0; i < leaves; ++i) {
        int count = rng() % 5 == 0 ? 5 + int(rng() % 5) : 1 + int(rng() % 4);
        wh.child[i] = int(refs.size());
        wh.count[i] = count;
        t += u01(rng) * 0.5f; // entries in order, as sorted_slots gives them
        wh.tnear[i] = t;
        slot[i] = i;
        for (int j = 0; j < count; ++j) refs.push_back(int(rng() % caps.size()));
      }
      pairs += leaves / 2;
      std::vector<Capsule> leaf(refs.size());
      for (std::size_t j = 0; j < refs.size(); ++j) leaf[j] = caps[std::size_t(refs[j])];
      Rows rows = capsule_rows(leaf);
      Geometry g{MASQ_PRIM_CAPSULE, 0, int(caps.size()), 0};
      KernelData kd{};
      kd.capsules = caps.data();
      kd.refs = refs.data();
      kd.geoms = &g;
      kd.leaf_capsule_rows = rows.rows.data();
      kd.leaf_capsule_stride = rows.stride;
      Probe p = random_probe(rng, caps[std::size_t(refs[0])], 1.0f);
      k::Nearest start = k::nearest_none(p.tmax);
      if (!any && rng() % 3 == 0) start.t = t * u01(rng); // a hit found earlier cuts later leaves off
      k::LeafOut got = k::capsule_leaves(kd, wh, slot, leaves, 0, 3, p.o, p.d, p.tmin, start);
      // The one-source leaves loop.
      k::Nearest want = start;
      int calls = 0;
      for (int i = 0; i < leaves && !(any && want.prim >= 0); ++i) {
        if (wh.tnear[i] > want.t) continue;
        for (int j = 0; j < wh.count[i]; ++j) {
          int prim = refs[std::size_t(wh.child[i] + j)];
          ++calls;
          k::PrimHit ph = k::intersect_capsule(caps[std::size_t(prim)], p.o, p.d, p.tmin, want.t);
          want = k::nearest_take(want, ph, prim, 0, 3);
          if (any && want.prim >= 0) break;
        }
      }
      bool same = got.nearest.prim == want.prim && bits(got.nearest.t) == bits(want.t) &&
                  bits(got.nearest.normal.x) == bits(want.normal.x) && bits(got.nearest.u) == bits(want.u) &&
                  got.isect_calls == calls;
      hits += want.prim >= 0;
      if (!same && mismatches++ == 0)
        first = std::to_string(leaves) + " leaves" + (any ? " (any hit)" : "") + ": prim " +
                std::to_string(got.nearest.prim) + " t " + std::to_string(got.nearest.t) + " calls " +
                std::to_string(got.isect_calls) + " vs prim " + std::to_string(want.prim) + " t " +
                std::to_string(want.t) + " calls " + std::to_string(calls);
    }
  }
  k::MASQ_ANY_HIT = false;
  EXPECT_EQ(mismatches, 0) << first;
  EXPECT_GT(hits, 40000 / 5);
  EXPECT_GT(pairs, 40000);
}
