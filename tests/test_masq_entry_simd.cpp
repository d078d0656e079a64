// The cpu dialect's four-lane unit-box test of compact masquerade entries
// (kernels/masq_entry_simd_cpp.h) against the one-source test it replaces on cpu:
// affine_from_masq, affine_point, affine_vector, then hit_unit_box_padded (robust) or
// hit_unit_box (fast). The scalar test answers only in or out, so each lane's entry and
// exit distances are probed at their own bits: with the window ending exactly at the
// lane's entry the scalar test must say in, one float earlier out; with it starting
// exactly at the lane's exit in, one float later out. Entries: the compact entries of
// real masq structures (curves and capsules of a generated hair scene, under a random
// instance map), every leaf size 1-4 and each entry in every lane; rays: from far away
// and from inside the boxes, axis-parallel directions among them (safe_rcp's 1e30).
#include "bvh/twolevel/build_accel.h"
#include "kernels/traverse.h"
#include "scenes/strand_generators.h"
#include "tests/random_affine.h"
#include <gtest/gtest.h>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

using namespace masq;
namespace k = masq::kernel::v_default;

namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

// The scalar test of one entry on the window [tmin, tmax], as the one-source TLAS walk makes it.
bool scalar_in_box(const kernel::MasqInstance& c, glm::vec3 wo, glm::vec3 wd, float tmin, float tmax, float t_bound,
                   bool robust) {
  k::Affine m = k::affine_from_masq(c);
  glm::vec3 oo = k::affine_point(m, wo);
  glm::vec3 od = k::affine_vector(m, wd);
  return robust ? k::hit_unit_box_padded(m, wo, wd, oo, od, tmin, tmax, t_bound) : k::hit_unit_box(oo, od, tmin, tmax);
}

std::vector<kernel::MasqInstance> compact_entries(PrimType type, std::uint64_t seed) {
  HairParams hp;
  hp.strands = 60;
  hp.seed = seed;
  hp.type = type;
  Scene s = make_hair_scene(hp);
  std::mt19937_64 rng(seed);
  s.instances.at(0).object_to_world = masq::test::random_affine(rng);
  PackedScene ps = build_accel(s, Method::Masq);
  return {ps.masq_instances.begin(), ps.masq_instances.end()};
}

} // namespace

TEST(MasqEntrySimd, LanesGiveTheScalarTestsBits) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  long probes = 0, entered = 0;
  for (PrimType type : {PrimType::Curve, PrimType::Capsule}) {
    std::vector<kernel::MasqInstance> entries = compact_entries(type, type == PrimType::Curve ? 3 : 4);
    ASSERT_GE(entries.size(), 100u);
    for (int trial = 0; trial < 4000; ++trial) {
      const int n = 1 + trial % 4;
      int refs[4];
      for (int j = 0; j < n; ++j) refs[j] = -1 - int(rng() % entries.size());
      // Aimed at the first entry's box centre (its translation maps it to the origin of
      // the unit box: the centre is where the inverse map sends 0), from far away or
      // from near it; every eighth ray along an axis.
      k::Affine m0 = k::affine_from_masq(entries[std::size_t(-1 - refs[0])]);
      glm::vec3 centre = glm::inverse(glm::mat3(glm::vec3(m0.r0.x, m0.r1.x, m0.r2.x), glm::vec3(m0.r0.y, m0.r1.y, m0.r2.y),
                                                glm::vec3(m0.r0.z, m0.r1.z, m0.r2.z))) *
                         -m0.t;
      glm::vec3 d = glm::vec3(u(rng), u(rng), u(rng));
      if (trial % 8 == 0) d = glm::vec3(0.0f, 0.0f, 0.0f), d[trial / 8 % 3] = u(rng) < 0 ? -1.0f : 1.0f;
      if (!(glm::dot(d, d) > 0.0f)) d = glm::vec3(0.0f, 1.0f, 0.0f);
      const float back = trial % 3 == 0 ? 0.0f : (trial % 3 == 1 ? 0.01f : 3.0f);
      glm::vec3 o = centre - back * d + 0.002f * glm::vec3(u(rng), u(rng), u(rng));
      const float t_bound = back + 5.0f * (1.0f + u(rng));
      for (bool robust : {true, false}) {
        kernel::simd::EntryBoxes4 eb = kernel::simd::entry_boxes4(entries.data(), refs, n, o, d, t_bound, robust);
        for (int j = 0; j < n; ++j) {
          const kernel::MasqInstance& c = entries[std::size_t(-1 - refs[j])];
          const float tn = eb.tn[j], tf = eb.tf[j];
          auto agree = [&](float tmin, float tmax) {
            ++probes;
            EXPECT_EQ(kernel::simd::entry_in_box(eb, j, tmin, tmax), scalar_in_box(c, o, d, tmin, tmax, t_bound, robust))
                << "entry " << -1 - refs[j] << " lane " << j << " of " << n << (robust ? " robust" : " fast") << " window ["
                << tmin << ", " << tmax << "], lane interval [" << tn << ", " << tf << "]";
          };
          agree(-kInf, kInf);
          if (!(tn <= tf)) continue;
          ++entered;
          agree(-kInf, tn);
          agree(-kInf, std::nextafter(tn, -kInf));
          agree(tf, kInf);
          agree(std::nextafter(tf, kInf), kInf);
        }
      }
    }
  }
  // The probes must have met both outcomes, at the boundaries too.
  EXPECT_GT(entered, probes / 10);
  EXPECT_LT(entered * 5, probes);
}
