// The cpu's packet walk (kernels/packet_walk_cpp.h) against the single-ray walk it
// stands in for (trace_closest): every ray the packet answers must get trace_closest's
// hit bit for bit (t, primitive, normal, u, v), on a pinhole camera's 512 x 512 rays
// (the users' sample size), in every node format, through hair of chained capsules in
// one BLAS (ref) and through hair of curves or capsules as a TLAS of masquerade entries
// (masq). The packet must answer most rays (else this test checks nothing) and leave to
// trace_closest every ray that takes a hit at exactly the distance of one it holds: on
// hair whose every capsule or curve is there twice, every hit is such a tie. Then the
// cpu backend end to end: its counter-free trace (packets) against its counting one (one
// ray at a time).
#include "bvh/twolevel/build_accel.h"
#include "host/backend.h"
#include "host/cpu/entry_curves.h"
#include "host/cpu/leaf_capsules.h"
#include "host/scene_arrays.h"
#include "host/scene_variant.h"
#include "host/trace_faults.h"
#include "kernels/packet_walk_cpp.h"
#include "scenes/camera.h"
#include "scenes/strand_generators.h"
#include <gtest/gtest.h>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

using namespace masq;
namespace k = masq::kernel::v_default;

namespace {

constexpr int kSide = 512; // the camera rays of `masq bench` and the peers suite

bool same_hit(const kernel::Hit& a, const kernel::Hit& b) { return std::memcmp(&a, &b, sizeof a) == 0; }

template <class T> void twice(std::vector<T>& prims) {
  const std::size_t n = prims.size();
  for (std::size_t i = 0; i < n; ++i) prims.push_back(prims[i]);
}

Scene hair(bool every_strand_twice, PrimType type = PrimType::Capsule) {
  HairParams p;
  p.strands = 3000;
  p.type = type;
  Scene s = make_hair_scene(p);
  if (every_strand_twice) {
    twice(s.geometries.at(0).capsules);
    twice(s.geometries.at(0).curves);
  }
  return s;
}

PackedScene packed(const Scene& s, NodeFormat nodes, Method method = Method::Ref,
                   CurveIsect isect = CurveIsect::Roving) {
  AccelOptions accel;
  accel.builder.kind = Builder::Sah4;
  accel.nodes = nodes;
  accel.curve_isect = isect;
  return build_accel(s, method, accel);
}

struct PacketCount {
  int answered = 0, left = 0, answered_hits = 0, differing = 0;
};

// Every packet of the camera's rays through trace_packet_closest (with packet_budget
// steps, if given, instead of the scene's step budget); each ray it answers compared
// with trace_closest's hit.
// The cpu's kernel data of ps, with its copies (as the cpu backend's set_scene makes
// them), and the default unit's switches set for ps.
struct CpuKernel {
  LeafCapsuleRows rows;
  HugePageVector<EntryCurve> curves;
  kernel::KernelData kd;
  explicit CpuKernel(const PackedScene& ps) {
    const KernelVariant v = kernel_variant(ps.features, {false, false});
#define MASQ_TEST_SET_SWITCH(NAME, key, T, DEF, ID, units, source) k::NAME = static_cast<T>(v.key);
    MASQ_VARIANTS(MASQ_TEST_SET_SWITCH)
#undef MASQ_TEST_SET_SWITCH
    leaf_capsules(ps, rows);
    entry_curves(ps, curves);
    kd = kernel_data(scene_array_data(ps));
    kd.leaf_capsule_rows = rows.rows.data();
    kd.leaf_capsule_stride = rows.stride;
    kd.entry_curves = curves.empty() ? nullptr : &curves.front().curve;
    kd.entry_packets = entry_packets(ps) ? 1 : 0;
  }
};

PacketCount packets_against_single_walk(const PackedScene& ps, const std::vector<kernel::Ray>& rays,
                                        int packet_budget = 0) {
  const CpuKernel cpu(ps);
  const kernel::KernelData& kd = cpu.kd;
  const int budget = step_budget(ps.node_count());
  EXPECT_TRUE(k::packet_walk_applies(kd, ps.tlas_root));
  PacketCount c;
  for (std::size_t i = 0; i + k::kPacketRays <= rays.size(); i += k::kPacketRays) {
    EXPECT_TRUE(k::packet_common_origin(rays.data() + i));
    kernel::Hit got[k::kPacketRays];
    const unsigned left =
        k::trace_packet_closest(kd, rays.data() + i, got, ps.tlas_root, packet_budget > 0 ? packet_budget : budget);
    for (int r = 0; r < k::kPacketRays; ++r) {
      if ((left >> r) & 1u) {
        ++c.left;
        continue;
      }
      const kernel::Hit want = k::trace_closest(kd, rays[i + std::size_t(r)], ps.tlas_root, budget).hit;
      ++c.answered;
      c.answered_hits += want.prim >= 0;
      c.differing += !same_hit(got[r], want);
    }
  }
  return c;
}

// The packets of hair's camera rays: every ray they answer as trace_closest does, most
// rays answered, a twentieth of them hits at least.
void expect_answers_as_single_walk(const PackedScene& ps, const std::vector<kernel::Ray>& rays) {
  const PacketCount c = packets_against_single_walk(ps, rays);
  EXPECT_EQ(c.differing, 0) << c.answered << " answered";
  std::printf("%d answered (%d hits), %d left\n", c.answered, c.answered_hits, c.left);
  EXPECT_GT(c.answered, 9 * int(rays.size()) / 20) << c.left << " left to trace_closest";
  EXPECT_GT(c.answered_hits, int(rays.size()) / 20);
}

// The same through hair whose every strand is there twice: every hit is a tie, left to
// trace_closest, and the rays that hit nothing are still answered.
void expect_ties_left(const PackedScene& ps, const std::vector<kernel::Ray>& rays) {
  const PacketCount c = packets_against_single_walk(ps, rays);
  EXPECT_EQ(c.differing, 0);
  EXPECT_EQ(c.answered_hits, 0) << "every hit has a twin at the same distance";
  EXPECT_GT(c.left, int(rays.size()) / 20);
  EXPECT_GT(c.answered, 0);
}

class PacketWalk : public ::testing::TestWithParam<NodeFormat> {};

TEST_P(PacketWalk, AnswersAsTheSingleRayWalk) {
  const Scene s = hair(false);
  expect_answers_as_single_walk(packed(s, GetParam()), make_camera_rays(s.camera, kSide, kSide));
}

TEST_P(PacketWalk, LeavesTiesToTheSingleRayWalk) {
  const Scene s = hair(true);
  expect_ties_left(packed(s, GetParam()), make_camera_rays(s.camera, kSide, kSide));
}

// A packet that would step past its budget hands every ray back (the single-ray walk
// then reports the fault, if there is one): with one step, only packets that miss the
// root's children are answered.
TEST_P(PacketWalk, HandsEveryRayBackPastTheBudget) {
  const Scene s = hair(false);
  const PackedScene ps = packed(s, GetParam());
  const std::vector<kernel::Ray> rays = make_camera_rays(s.camera, kSide, kSide);
  const PacketCount c = packets_against_single_walk(ps, rays, 1);
  EXPECT_EQ(c.differing, 0);
  EXPECT_EQ(c.answered_hits, 0);
  EXPECT_GT(c.left, int(rays.size()) / 20);
}

INSTANTIATE_TEST_SUITE_P(NodeFormats, PacketWalk,
                         ::testing::Values(NodeFormat::W4, NodeFormat::W8, NodeFormat::Q8, NodeFormat::O4),
                         [](const ::testing::TestParamInfo<NodeFormat>& p) { return std::string(node_format_name(p.param)); });

// A TLAS of masquerade entries: curves (roving, the peers suite's intersector, and the
// certified subdivision) and capsules, each node format.
struct EntryCase {
  PrimType type;
  CurveIsect isect;
  NodeFormat nodes;
};

class EntryPacketWalk : public ::testing::TestWithParam<EntryCase> {
 protected:
  PackedScene scene(bool every_strand_twice) const {
    return packed(hair(every_strand_twice, GetParam().type), GetParam().nodes, Method::Masq, GetParam().isect);
  }
};

TEST_P(EntryPacketWalk, AnswersAsTheSingleRayWalk) {
  const PackedScene ps = scene(false);
  ASSERT_TRUE(entry_packets(ps));
  expect_answers_as_single_walk(ps, make_camera_rays(hair(false).camera, kSide, kSide));
}

TEST_P(EntryPacketWalk, LeavesTiesToTheSingleRayWalk) {
  expect_ties_left(scene(true), make_camera_rays(hair(false).camera, kSide, kSide));
}

INSTANTIATE_TEST_SUITE_P(
    Entries, EntryPacketWalk,
    ::testing::Values(EntryCase{PrimType::Curve, CurveIsect::Roving, NodeFormat::W4},
                      EntryCase{PrimType::Curve, CurveIsect::Roving, NodeFormat::W8},
                      EntryCase{PrimType::Curve, CurveIsect::Roving, NodeFormat::Q8},
                      EntryCase{PrimType::Curve, CurveIsect::Roving, NodeFormat::O4},
                      EntryCase{PrimType::Curve, CurveIsect::Phantom, NodeFormat::W8},
                      EntryCase{PrimType::Capsule, CurveIsect::Roving, NodeFormat::W8}),
    [](const ::testing::TestParamInfo<EntryCase>& p) {
      return std::string(p.param.type == PrimType::Curve ? "curves_" : "capsules_") +
             (p.param.isect == CurveIsect::Roving ? "roving_" : "phantom_") + node_format_name(p.param.nodes);
    });

// Entry packets are for TLAS of masquerade entries of capsules and curves alone: a ref
// BLAS has none, and an entry of another primitive (here a triangle mesh beside the hair)
// turns them off.
TEST(EntryPacketWalk, OnlyForEntriesOfCapsulesAndCurves) {
  EXPECT_FALSE(entry_packets(packed(hair(false, PrimType::Curve), NodeFormat::W8, Method::Ref)));
  EXPECT_TRUE(entry_packets(packed(hair(false, PrimType::Curve), NodeFormat::W8, Method::Masq)));
  Scene mixed = hair(false, PrimType::Curve);
  Geometry ground;
  ground.type = PrimType::Triangle;
  ground.vertices = {{-1, -1, 0}, {1, -1, 0}, {0, 1, 0}};
  ground.triangles = {{0, 1, 2}};
  mixed.geometries.push_back(ground);
  mixed.instances.push_back(Instance{std::uint32_t(mixed.geometries.size() - 1), Affine3{}});
  EXPECT_FALSE(entry_packets(packed(mixed, NodeFormat::W8, Method::Masq)));
}

// The cpu backend refills its leaf copy in the storage of the scene before
// (host/cpu/leaf_capsules.h): a copy refilled after a larger scene's must be the copy
// made fresh, padding included.
TEST(PacketWalk, LeafCopyRefilledAsMadeFresh) {
  const PackedScene small = packed(hair(false), NodeFormat::W8);
  LeafCapsuleRows fresh, reused;
  leaf_capsules(small, fresh);
  leaf_capsules(packed(hair(true), NodeFormat::W8), reused);
  ASSERT_GT(reused.rows.size(), fresh.rows.size());
  leaf_capsules(small, reused);
  EXPECT_EQ(reused.stride, fresh.stride);
  ASSERT_EQ(reused.rows.size(), fresh.rows.size());
  EXPECT_EQ(std::memcmp(reused.rows.data(), fresh.rows.data(), fresh.rows.size() * sizeof(float)), 0);
}

// The cpu backend's counter-free trace of rays through ps (packets, entries nearest box
// first) against its counting one (one ray at a time, reference order): the same hits,
// bit for bit, a twentieth of the rays hits at least.
void expect_traces_as_with_counters(const PackedScene& ps, const std::vector<kernel::Ray>& rays,
                                    const std::string& what) {
  std::unique_ptr<Backend> cpu = make_backend("cpu");
  cpu->set_scene(ps);
  std::vector<kernel::Hit> free_of_counters(rays.size()), counted(rays.size());
  std::vector<kernel::RayStats> stats(rays.size());
  cpu->trace(rays, free_of_counters, {});
  cpu->trace(rays, counted, stats);
  int differing = 0, hits = 0;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    differing += !same_hit(free_of_counters[i], counted[i]);
    hits += counted[i].prim >= 0;
  }
  EXPECT_EQ(differing, 0) << what;
  EXPECT_GT(hits, int(rays.size()) / 20) << what;
}

// For a BLAS of capsules (ref) and a TLAS of curve entries (masq) alike.
TEST(PacketWalk, CpuBackendTracesAsWithCounters) {
  for (bool twice : {false, true}) {
    for (Method method : {Method::Ref, Method::Masq}) {
      const Scene s = hair(twice, method == Method::Ref ? PrimType::Capsule : PrimType::Curve);
      const PackedScene ps = packed(s, NodeFormat::O4, method);
      expect_traces_as_with_counters(ps, make_camera_rays(s.camera, kSide, kSide),
                                     std::string(twice ? "every strand twice, " : "hair, ") + method_name(method));
    }
  }
}

// Rays that leave distinct points (the camera's, each origin moved by a few ulps), so
// that the cpu traces each alone: a TLAS leaf's entries nearest box first
// (kernels/traverse.h, entry_leaf_nearest_first) against the counting trace's reference
// order, through curves and capsules, hair and hair whose every strand is there twice.
TEST(EntryLeaf, CpuBackendTracesAsWithCounters) {
  for (PrimType type : {PrimType::Curve, PrimType::Capsule}) {
    for (bool twice : {false, true}) {
      const Scene s = hair(twice, type);
      const PackedScene ps = packed(s, NodeFormat::W8, Method::Masq);
      ASSERT_TRUE(entry_packets(ps));
      std::vector<kernel::Ray> rays = make_camera_rays(s.camera, kSide, kSide);
      for (std::size_t i = 0; i < rays.size(); ++i)
        for (std::size_t n = 0; n <= i % std::size_t(k::kPacketRays); ++n)
          rays[i].org[0] = std::nextafter(rays[i].org[0], INFINITY);
      expect_traces_as_with_counters(ps, rays,
                                     std::string(twice ? "every strand twice, " : "hair, ") + prim_type_name(type));
    }
  }
}

// A leaf of a curve and its twin whose boxes are given in the reverse of the reference
// order (the twin's nearer): the two hits tie at one distance, and the leaf must keep
// the reference order's (the twin's: taken last, at the distance it ties), not the one
// the box order would leave.
TEST(EntryLeaf, TiedHitsKeepTheReferenceOrder) {
  const Scene s = hair(true, PrimType::Curve);
  const PackedScene ps = packed(s, NodeFormat::W8, Method::Masq);
  const std::size_t strands = s.geometries.at(0).curves.size() / 2;
  std::vector<int> entry_of(2 * strands, -1);
  for (std::size_t e = 0; e < ps.masq_instances.size(); ++e) entry_of.at(std::size_t(ps.masq_instances[e].prim)) = int(e);
  const CpuKernel cpu(ps);
  const int budget = step_budget(ps.node_count());
  int ties = 0;
  for (const kernel::Ray& ray : make_camera_rays(s.camera, 64, 64)) {
    const kernel::Hit h = k::trace_closest(cpu.kd, ray, ps.tlas_root, budget).hit;
    if (h.prim < 0) continue;
    const std::size_t p = std::size_t(h.prim) % strands; // the first copy; its twin p + strands
    const int refs[2] = {-1 - entry_of.at(p), -1 - entry_of.at(p + strands)};
    kernel::simd::EntryBoxes4 eb{{-1.0f, -2.0f, 0.0f, 0.0f}, {INFINITY, INFINITY, 0.0f, 0.0f}};
    const glm::vec3 wo(ray.org[0], ray.org[1], ray.org[2]), wd(ray.dir[0], ray.dir[1], ray.dir[2]);
    k::Nearest in_order = k::nearest_none(ray.tmax), box_first = in_order;
    for (int j = 0; j < 2; ++j) {
      const kernel::MasqInstance c = ps.masq_instances[std::size_t(-1 - refs[j])];
      const kernel::MasqOwner owner = ps.masq_owners[k::masq_owner_index(c)];
      in_order = k::masquerade_hit(cpu.kd, refs[j], owner.geom, c.prim, owner.scene_inst, wo, wd, ray.tmin, in_order);
    }
    k::entry_leaf_nearest_first(cpu.kd, refs, 2, eb, wo, wd, ray.tmin, box_first);
    ASSERT_GE(in_order.prim, 0);
    ASSERT_EQ(in_order.prim, int(p + strands)) << "the twin, taken last at the same distance";
    EXPECT_EQ(std::memcmp(&box_first, &in_order, sizeof in_order), 0) << "ray hitting curve " << p;
    ++ties;
  }
  EXPECT_GT(ties, 64 * 64 / 20);
}

} // namespace
