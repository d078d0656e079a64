// The parallel host build (bvh/binary/parallel.h, docs/builders.md): with any thread count
// every method and builder makes the same structure as the serial build, byte for byte
// (nodes, references, instances, compact entries, frames, leaf orders), and the float
// sums of its statistics are the same to the last bit.
#include "bvh/twolevel/build_accel.h"
#include "bvh/binary/binned_sah.h"
#include "bvh/binary/parallel.h"
#include "bvh/binary/partition_in_chunks.h"
#include "masq/error.h"
#include "scenes/generators.h"
#include "scenes/loaders/load_any.h"
#include "scenes/strand_generators.h"
#include <gtest/gtest.h>
#include <glm/gtc/matrix_transform.hpp>
#include <cmath>
#include <cstring>
#include <random>

using namespace masq;

namespace {

// Thread counts compared with the serial build: more than this machine's cores is
// allowed (the arena takes what the hardware has).
const int kThreadCounts[] = {2, 3, 8};

// Bytes of a vector of trivially copyable records.
template <class T, class Allocator>
std::string bytes_of(const std::vector<T, Allocator>& v) {
  return std::string(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(T));
}

std::string bits_of(double x) { return std::string(reinterpret_cast<const char*>(&x), sizeof x); }

// Every array of the structure and the statistics that are sums, as bytes, named.
std::vector<std::pair<std::string, std::string>> arrays_of(const PackedScene& ps) {
  std::vector<std::pair<std::string, std::string>> out = {
      {"nodes", bytes_of(ps.nodes)},
      {"nodes8", bytes_of(ps.nodes8)},
      {"qnodes", bytes_of(ps.qnodes)},
      {"onodes", bytes_of(ps.onodes)},
      {"refs", bytes_of(ps.refs)},
      {"instances", bytes_of(ps.instances)},
      {"masq_instances", bytes_of(ps.masq_instances)},
      {"masq_owners", bytes_of(ps.masq_owners)},
      {"frames", bytes_of(ps.frames)},
      {"geoms", bytes_of(ps.geoms)},
      {"capsules", bytes_of(ps.capsules)},
      {"frame_object_to_world", bytes_of(ps.frame_object_to_world)},
      {"instance_object_to_world", bytes_of(ps.instance_object_to_world)},
      {"tlas_leaf_order", bytes_of(ps.tlas_leaf_order)},
      {"tlas_root", std::to_string(ps.tlas_root)},
      {"sah_cost", bits_of(ps.stats.sah_cost)},
      {"blas_sah_cost", bits_of(ps.stats.blas_sah_cost)},
      {"obb_area", bits_of(ps.stats.obb_area)},
      {"aabb_area", bits_of(ps.stats.aabb_area)},
      {"model_cost", bits_of(ps.stats.model_cost)},
      {"method", std::to_string(int(ps.stats.auto_choice)) + "/" + std::to_string(int(ps.method))},
  };
  for (std::size_t g = 0; g < ps.geometry_leaf_order.size(); ++g)
    out.push_back({"geometry_leaf_order[" + std::to_string(g) + "]", bytes_of(ps.geometry_leaf_order[g])});
  return out;
}

// Builds scene with method and builder serially and with every count of kThreadCounts,
// and expects the same bytes in every array. Returns the serial structure.
PackedScene expect_same_at_every_thread_count(const Scene& scene, Method method, AccelOptions opt) {
  SCOPED_TRACE(std::string(method_name(method)) + ", builder " + builder_name(opt.builder.kind));
  opt.build_threads = 1;
  PackedScene serial = build_accel(scene, method, opt);
  auto want = arrays_of(serial);
  for (int threads : kThreadCounts) {
    opt.build_threads = threads;
    auto got = arrays_of(build_accel(scene, method, opt));
    EXPECT_EQ(got.size(), want.size());
    for (std::size_t i = 0; i < std::min(got.size(), want.size()); ++i)
      EXPECT_TRUE(got[i].second == want[i].second)
          << want[i].first << " differs with " << threads << " threads (" << got[i].second.size() << " vs "
          << want[i].second.size() << " bytes)";
  }
  return serial;
}

// Hair of capsules: some 40K primitives, above the builder's chunked binning (32K) and
// subtree-task (4K) sizes, so those parallel paths run.
Scene capsule_hair() {
  HairParams p;
  p.strands = 5000;
  p.points = 9;
  p.type = PrimType::Capsule;
  return make_hair_scene(p);
}

Affine3 rotated(double angle, glm::dvec3 axis, glm::dvec3 shift) {
  Affine3 a;
  a.linear = glm::dmat3(glm::rotate(glm::dmat4(1.0), angle, glm::normalize(axis))) * 1.5;
  a.translation = shift;
  return a;
}

// Strands, spheres, curves and a mesh, some instanced twice under rotations: per-geometry
// BLAS, masquerade entries of several owners and cluster instances shared by instances.
Scene mixed_scene() {
  Scene s = make_default_scene();
  std::uint32_t first = std::uint32_t(s.geometries.size());
  s.geometries.push_back(make_random_geometry(PrimType::Sphere, 1500, 0.004f, 0.02f, 1.0, 7));
  s.geometries.push_back(make_random_geometry(PrimType::Curve, 600, 0.002f, 0.01f, 1.0, 8));
  s.geometries.push_back(make_random_mesh(3000, 1.0, 9));
  s.geometries.push_back(make_random_geometry(PrimType::RoundCone, 2500, 0.002f, 0.01f, 1.0, 10));
  for (std::uint32_t g = first; g < s.geometries.size(); ++g) {
    s.instances.push_back({g, rotated(0.3 * g, {1, 2, 3}, {0.5 * g, 0, 0})});
    s.instances.push_back({g, rotated(-0.7 * g, {3, -1, 2}, {0, 0.5 * g, 1})});
  }
  return s;
}

const Method kAllMethods[] = {Method::Ref, Method::Masq, Method::Cluster, Method::Auto};

TEST(ParallelBuild, HairEveryMethodSameBytes) {
  Scene s = capsule_hair();
  ASSERT_GT(s.primitive_count(), 32768u);
  for (Method m : kAllMethods) expect_same_at_every_thread_count(s, m, {});
}

// o4: the frames of sibling subtrees are chosen at once (bvh/nodes/wide_bvh.cpp,
// plan_frames), here above its threshold of references per node.
TEST(ParallelBuild, OrientedNodesSameBytes) {
  Scene s = capsule_hair();
  AccelOptions o4;
  o4.nodes = NodeFormat::O4;
  PackedScene ps = expect_same_at_every_thread_count(s, Method::Ref, o4);
  EXPECT_GT(ps.stats.oriented_nodes, 0u); // rotated nodes were chosen, not only axis-aligned ones
}

TEST(ParallelBuild, MeshSameBytes) {
  Scene s;
  s.geometries.push_back(make_random_mesh(40000, 1.0, 3));
  s.instances.push_back({0, {}});
  // Triangles stay in a BLAS under every method; ref and auto cover both paths.
  for (Method m : {Method::Ref, Method::Auto}) expect_same_at_every_thread_count(s, m, {});
}

TEST(ParallelBuild, MixedSceneEveryMethodAndBuilderSameBytes) {
  Scene s = mixed_scene();
  for (Builder b : all_builders())
    for (Method m : kAllMethods) {
      // The mix of auto has every instance kind in one TLAS: with it and ref every
      // builder's BLAS and TLAS paths run; the other methods once, with the default.
      if (b != Builder::Sah && m != Method::Ref && m != Method::Auto) continue;
      AccelOptions opt;
      opt.builder.kind = b;
      opt.auto_select = AutoSelect::MixOnly;
      expect_same_at_every_thread_count(s, m, opt);
    }
  // Full masquerade instances, owners running out, node formats other than w4.
  AccelOptions full;
  full.masq_instances = MasqInstances::Full;
  expect_same_at_every_thread_count(s, Method::Masq, full);
  AccelOptions few_owners;
  few_owners.masq_owner_limit = 3;
  expect_same_at_every_thread_count(s, Method::Masq, few_owners);
  for (NodeFormat f : {NodeFormat::W8, NodeFormat::Q8, NodeFormat::O4}) {
    AccelOptions nodes;
    nodes.nodes = f;
    expect_same_at_every_thread_count(s, Method::Auto, nodes);
  }
}

// The real fur the build times are measured on (docs/builders.md), when the data is there.
TEST(ParallelBuild, BearFurSameBytes) {
  Scene s;
  try {
    s = load_scene_file(std::string(MASQ_DATA_DIR) + "/hair/tressfx3_bear.tfx");
  } catch (const Error& e) {
    GTEST_SKIP() << e.what();
  }
  for (Method m : {Method::Ref, Method::Masq}) expect_same_at_every_thread_count(s, m, {});
}

// The binned SAH alone, on boxes with many equal coordinates (signed zeros, coincident
// centroids, a box shared by many): ties are where a merge in another order would show.
TEST(ParallelBuild, BinnedSahTiesSameTree) {
  std::mt19937_64 rng(5);
  std::uniform_int_distribution<int> cell(-3, 3);
  std::vector<Aabb> boxes(70000);
  std::uniform_int_distribution<int> size(0, 2);
  for (Aabb& b : boxes) {
    glm::dvec3 c(cell(rng), cell(rng), cell(rng));
    if (cell(rng) > 0) c *= -0.0; // +0 and -0 corners
    b.lo = c;
    b.hi = c + glm::dvec3(0.5 * size(rng)); // points among them: coincident centroids
  }
  BinaryBvh serial, parallel;
  run_with_build_threads(1, [&] { serial = build_binned_sah(boxes); });
  run_with_build_threads(3, [&] { parallel = build_binned_sah(boxes); });
  ASSERT_EQ(serial.nodes.size(), parallel.nodes.size());
  EXPECT_EQ(serial.order, parallel.order);
  EXPECT_EQ(0, std::memcmp(serial.nodes.data(), parallel.nodes.data(), serial.nodes.size() * sizeof(BinaryNode)));
}

// The chunked partition the binned SAH uses on long ranges gives std::partition's own
// (unstable) order: random ranges, predicates, chunk sizes and thread counts.
TEST(ParallelBuild, ChunkedPartitionIsStdPartition) {
  std::mt19937_64 rng(11);
  for (int trial = 0; trial < 200; ++trial) {
    int n = int(rng() % 3000), first = int(rng() % 50), chunk = 1 + int(rng() % 300);
    std::vector<int> order(std::size_t(first + n + 17));
    for (int& v : order) v = int(rng() % 1000);
    int cut = int(rng() % 1001); // 0 and 1000: nothing or everything goes left
    auto goes_left = [&](int v) { return v < cut; };
    std::vector<int> want = order, got = order;
    int want_mid = int(std::partition(want.begin() + first, want.begin() + first + n, goes_left) - want.begin());
    int got_mid = 0;
    run_with_build_threads(1 + trial % 3, [&] { got_mid = partition_in_chunks(got, first, n, chunk, goes_left); });
    ASSERT_EQ(want_mid, got_mid) << "trial " << trial;
    ASSERT_EQ(want, got) << "trial " << trial << ": n " << n << ", chunk " << chunk;
  }
}

TEST(ParallelBuild, NegativeThreadCountIsAnError) {
  Scene s = make_default_scene();
  AccelOptions opt;
  opt.build_threads = -1;
  EXPECT_THROW(build_accel(s, Method::Ref, opt), Error);
}

} // namespace
