// Traversal that cannot finish is an error, never a hang or a silent miss (kernels/
// traverse.h, kernels/bv_traverse.h, host/trace_faults.h), on the backends whose kernels
// walk masq's own structures: cpu, vulkan and opencl, two-level (a BLAS walk under ref, the
// TLAS walk under masq) and bounding-volume hierarchies.
//  - A corrupt structure: a node whose one inner child points back at it (a cycle no
//    correct walk takes). Its rays exhaust the step budget.
//  - A stack declared smaller than the structure's walks need: its deep rays fill it.
// Each must fail the trace with one error naming the backend, the device and how many rays
// stopped, and MASQ_DIAGNOSE must list the first rays' state. The ctest TIMEOUT guards the
// hang this replaces; nothing here is timed.
#include "bvh/bv/bv_scene.h"
#include "bvh/twolevel/build_accel.h"
#include "host/backend.h"
#include "host/bv_tracer.h"
#include "host/trace_faults.h"
#include "scenes/camera.h"
#include "scenes/generators.h"
#include <gtest/gtest.h>
#include <algorithm>
#include <functional>
#include <ostream>
#include <regex>
#include <string>
#include "tests/test_env.h"

using namespace masq;

namespace {

// The walks' starting nodes: ref's first BLAS with inner nodes, or the TLAS root.
std::int32_t walk_root(const PackedScene& ps) {
  if (ps.method != Method::Ref) return ps.tlas_root;
  for (const kernel::Instance& inst : ps.instances)
    if (inst.blas_root >= 0)
      for (int s = 0; s < MASQ_WIDTH; ++s)
        if (ps.nodes[inst.blas_root].count[s] == 0) return inst.blas_root;
  return -1;
}

int first_inner_slot(const kernel::WideNode& n) {
  for (int s = 0; s < MASQ_WIDTH; ++s)
    if (n.count[s] == 0) return s;
  return -1;
}

// p = the walk's root, c = its first inner child, g = c's first inner slot: p keeps only
// its slot of c, c only slot g, whose child becomes p. A ray entering both boxes then
// goes p, c, p, c, ... with nothing pushed, until the step budget stops it.
void make_cycle(PackedScene& ps) {
  const std::int32_t p = walk_root(ps);
  ASSERT_GE(p, 0);
  const int sc = first_inner_slot(ps.nodes[p]);
  ASSERT_GE(sc, 0);
  const std::int32_t c = ps.nodes[p].child[sc];
  const int sg = first_inner_slot(ps.nodes[c]);
  ASSERT_GE(sg, 0) << "the root's first inner child has no inner child";
  for (int s = 0; s < MASQ_WIDTH; ++s) {
    if (s != sc) ps.nodes[p].count[s] = -1;
    if (s != sg) ps.nodes[c].count[s] = -1;
  }
  ps.nodes[c].child[sg] = p;
}

// The count of rays stopped for `what` in the error, or -1 where the message does not say.
long stopped(const std::string& msg, const char* what) {
  std::smatch m;
  const std::regex count(std::string("(\\d+) ") + what);
  return std::regex_search(msg, m, count) ? std::stol(m[1]) : -1;
}

// The error `trace` throws (a test failure, and "", if it returns).
template <class Trace>
std::string error_of(Trace trace) {
  try {
    trace();
  } catch (const Error& e) {
    return e.what();
  }
  ADD_FAILURE() << "the trace returned";
  return "";
}

struct Case {
  std::string backend;
  Method method; // Ref: a BLAS walk; Masq: the TLAS walk
};
void PrintTo(const Case& c, std::ostream* os) { *os << c.backend << " " << method_name(c.method); }

class TraversalFaults : public ::testing::TestWithParam<Case> {
 protected:
  void SetUp() override {
    be_ = test::open_or_fail(GetParam().backend, [](const std::string& n) { return make_backend(n); });
    if (!be_) GTEST_SKIP() << GetParam().backend << " unavailable";
    scene_ = make_default_scene();
    rays_ = make_camera_rays(scene_.camera, 64, 64);
    packed_ = build_accel(scene_, GetParam().method);
    ASSERT_FALSE(packed_.features.single_blas && GetParam().method != Method::Ref);
  }
  // The error of tracing packed_ (a test failure if the trace does not throw).
  std::string trace_error() {
    be_->set_scene(packed_);
    std::vector<kernel::Hit> hits(rays_.size());
    return error_of([&] { be_->trace(rays_, hits, {}); });
  }
  std::unique_ptr<Backend> be_;
  Scene scene_;
  std::vector<kernel::Ray> rays_;
  PackedScene packed_;
};

TEST_P(TraversalFaults, CorruptStructureExhaustsTheStepBudget) {
  make_cycle(packed_);
  test::ScopedEnv no_listing("MASQ_DIAGNOSE", "0");
  const std::string msg = trace_error();
  SCOPED_TRACE(msg);
  EXPECT_NE(msg.find(be_->name() + " on '" + be_->device_name() + "'"), std::string::npos);
  EXPECT_NE(msg.find("of " + std::to_string(rays_.size()) + " rays"), std::string::npos);
  EXPECT_GT(stopped(msg, "past the step budget"), 0);
  EXPECT_EQ(stopped(msg, "on a full stack"), 0);
  EXPECT_NE(msg.find("MASQ_DIAGNOSE"), std::string::npos);
  // The diagnosis names the level the cycle is in and the nodes it runs between.
  test::ScopedEnv diagnose("MASQ_DIAGNOSE", "3");
  const std::string listed = trace_error();
  const char* level = GetParam().method == Method::Ref ? "in a BLAS walk" : "in a TLAS walk";
  EXPECT_NE(listed.find(std::string("past the step budget ") + level), std::string::npos) << listed;
  EXPECT_EQ(std::count(listed.begin(), listed.end(), '\n'), 3) << listed;
}

TEST_P(TraversalFaults, TooSmallStackFills) {
  // The walks need more than the smallest stack (8 entries, host/stack_size.h) on this scene.
  StackNeed& need = GetParam().method == Method::Ref ? packed_.features.blas_stack : packed_.features.tlas_stack;
  ASSERT_GT(need.entries, 8) << "the scene's walks are too shallow for this test";
  need.entries = 1;
  const std::string msg = trace_error();
  SCOPED_TRACE(msg);
  EXPECT_NE(msg.find("of " + std::to_string(rays_.size()) + " rays"), std::string::npos);
  EXPECT_GT(stopped(msg, "on a full stack"), 0);
}

TEST_P(TraversalFaults, SoundStructureTracesAndTheCheckCanBeSwitchedOff) {
  // The same scene unharmed traces without a fault, with the check on and off.
  be_->set_scene(packed_);
  std::vector<kernel::Hit> on(rays_.size()), off(rays_.size());
  be_->trace(rays_, on, {});
  {
    test::ScopedEnv no_check("MASQ_STEP_CHECK", "off");
    be_->trace(rays_, off, {});
  }
  int hits = 0;
  for (std::size_t i = 0; i < rays_.size(); ++i) {
    hits += on[i].prim >= 0;
    ASSERT_EQ(on[i].prim, off[i].prim) << "ray " << i;
    ASSERT_EQ(on[i].t, off[i].t) << "ray " << i;
    ASSERT_EQ(on[i].fault, 0);
  }
  EXPECT_GT(hits, 0);
}

std::vector<Case> cases() {
  std::vector<Case> out;
  for (const char* b : {"cpu", "vulkan", "opencl"})
    for (Method m : {Method::Ref, Method::Masq}) out.push_back({b, m});
  return out;
}
INSTANTIATE_TEST_SUITE_P(Backends, TraversalFaults, ::testing::ValuesIn(cases()),
                         [](const ::testing::TestParamInfo<Case>& i) {
                           return i.param.backend + "_" + method_name(i.param.method);
                         });

// The bounding-volume kernels: an inner node whose children become itself and its
// sibling (a cycle back to its parent's children), and a stack smaller than the depth.
class BvTraversalFaults : public ::testing::TestWithParam<std::string> {};

TEST_P(BvTraversalFaults, CycleAndSmallStackAreErrors) {
  std::unique_ptr<BvTracer> tracer =
      test::open_or_fail(GetParam(), [](const std::string& n) { return make_bv_tracer(n); });
  if (!tracer) GTEST_SKIP() << GetParam() << " unavailable";
  const Scene scene = make_default_scene();
  const std::vector<kernel::Ray> rays = make_camera_rays(scene.camera, 64, 64);
  BvOptions opt;
  opt.type = BvType::Aabb;
  const BvScene sound = build_bv_scene(scene, opt);
  auto bv_error = [&](const BvScene& s) {
    tracer->set_scene(s);
    std::vector<kernel::Hit> hits(rays.size());
    return error_of([&] { tracer->trace(rays, hits, {}); });
  };
  {
    BvScene cyc = sound;
    ASSERT_EQ(cyc.bv_aabb[0].count, 0);
    int c = cyc.bv_aabb[0].child; // an inner child of the root
    if (cyc.bv_aabb[c].count != 0) ++c;
    ASSERT_EQ(cyc.bv_aabb[c].count, 0);
    cyc.bv_aabb[c].child = c; // its children: itself and its sibling
    const std::string msg = bv_error(cyc);
    EXPECT_NE(msg.find("of " + std::to_string(rays.size()) + " rays"), std::string::npos) << msg;
    EXPECT_GT(stopped(msg, "on a full stack") + stopped(msg, "past the step budget"), 0) << msg;
  }
  {
    BvScene shallow = sound;
    ASSERT_GT(shallow.prims.features.blas_stack.entries, 8);
    shallow.prims.features.blas_stack.entries = 1;
    const std::string msg = bv_error(shallow);
    EXPECT_GT(stopped(msg, "on a full stack"), 0) << msg;
  }
  tracer->set_scene(sound);
  std::vector<kernel::Hit> hits(rays.size());
  tracer->trace(rays, hits, {});
}

INSTANTIATE_TEST_SUITE_P(Backends, BvTraversalFaults, ::testing::Values("cpu", "vulkan", "opencl"));

TEST(TraceFaults, MessageAndDiagnosis) {
  test::ScopedEnv no_listing("MASQ_DIAGNOSE", "0"); // whatever the caller's environment sets
  std::vector<kernel::Hit> hits(5);
  hits[1].fault = MASQ_FAULT_STEP_BUDGET | (MASQ_LEVEL_BLAS << 8);
  hits[1].fault_node = 42;
  hits[1].fault_depth = 3;
  hits[4].fault = MASQ_FAULT_STACK_FULL | (MASQ_LEVEL_TLAS << 8);
  hits[4].fault_node = 7;
  hits[4].fault_depth = 16;
  try {
    check_trace_faults("vulkan", "Some GPU", hits, 99);
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_STREQ(e.what(), "vulkan on 'Some GPU': the traversal stopped 2 of 5 rays (1 on a full stack, 1 past the "
                           "step budget of 99 steps): a cycle in the structure, or node data or stack entries read "
                           "wrong; MASQ_DIAGNOSE=8 lists the first rays' state");
  }
  test::ScopedEnv listing("MASQ_DIAGNOSE", "1");
  try {
    check_trace_faults("vulkan", "Some GPU", hits, 99);
    FAIL() << "no error";
  } catch (const Error& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("\n  ray 1: past the step budget in a BLAS walk at node 42, stack depth 3"), std::string::npos)
        << msg;
    EXPECT_EQ(msg.find("ray 4"), std::string::npos) << msg;
  }
  test::ScopedEnv bad("MASQ_DIAGNOSE", "many");
  EXPECT_THROW(diagnose_ray_count(), Error);
  hits[1].fault = hits[4].fault = 0;
  EXPECT_NO_THROW(check_trace_faults("cpu", "host", hits, 1));
}

} // namespace
