// Specialization constants frozen on the host (host/vulkan/spirv_specialize.h): every
// kernel module stays valid SPIR-V for every kind of variant, keeps its work-group size,
// loses the code its variant disables, and traces the same bits as the module the driver
// specializes itself (MASQ_VK_SPECIALIZE=driver) on every Vulkan backend.
#include "bvh/twolevel/build_accel.h"
#include "host/backend.h"
#include "host/vulkan/spirv_specialize.h"
#include "host/vulkan/trace_dispatch.h"
#include "masq/error.h"
#include "scenes/generators.h"
#include "spirv/rayquery_comp_spv.h"
#include "spirv/rtpipeline_rchit_spv.h"
#include "spirv/rtpipeline_rgen_spv.h"
#include "spirv/rtpipeline_rint_spv.h"
#include "spirv/rtpipeline_rmiss_spv.h"
#include "spirv/rtpipeline_triangle_rahit_spv.h"
#include "spirv/rtpipeline_triangle_rchit_spv.h"
#include "spirv/trace_bv_aabb_sized_spv.h"
#include "spirv/trace_bv_obb_sized_spv.h"
#include "spirv/trace_bv_scb_sized_spv.h"
#include "spirv/trace_bv_sphere_sized_spv.h"
#include "spirv/trace_comp_addr_spv.h"
#include "spirv/trace_comp_sized_spv.h"
#include "spirv/trace_comp_spv.h"
#include "tests/random_rays.h"
#include "tests/test_env.h"
#include <gtest/gtest.h>
#include <spirv-tools/libspirv.hpp>
#include <cstring>
#include <set>

using namespace masq;
using namespace masq::vk;

namespace {

constexpr std::uint32_t kOpDecorate = 71, kDecorationSpecId = 1, kDecorationBuiltIn = 11, kBuiltInWorkgroupSize = 25;

// The SpecIds still decorated in the module, and whether a WorkgroupSize built-in is.
struct Decorations {
  std::set<std::uint32_t> spec_ids;
  bool workgroup_size = false;
};
Decorations decorations(std::span<const std::uint32_t> m) {
  Decorations d;
  for (std::size_t at = 5; at < m.size(); at += m[at] >> 16) {
    if ((m[at] & 0xffff) != kOpDecorate) continue;
    if (m[at + 2] == kDecorationSpecId) d.spec_ids.insert(m[at + 3]);
    if (m[at + 2] == kDecorationBuiltIn && m[at + 3] == kBuiltInWorkgroupSize) d.workgroup_size = true;
  }
  return d;
}

std::string validation_errors(std::span<const std::uint32_t> m) {
  spvtools::SpirvTools tools(SPV_ENV_VULKAN_1_2);
  std::string log;
  tools.SetMessageConsumer([&](spv_message_level_t, const char*, const spv_position_t&, const char* text) {
    log += text;
    log += '\n';
  });
  return tools.Validate(m.data(), m.size()) ? "" : log;
}

struct NamedVariant {
  const char* name;
  KernelVariant v;
};
std::vector<NamedVariant> variants() {
  std::vector<NamedVariant> out{{"default", {}}};
  auto only = [](std::int32_t KernelVariant::*have) {
    KernelVariant v;
    v.triangles = v.capsules = v.round_cones = v.spheres = v.curves = v.ribbons = 0;
    v.*have = 1;
    return v;
  };
  out.push_back({"capsules", only(&KernelVariant::capsules)});
  NamedVariant curves{"curves roving, stats", only(&KernelVariant::curves)};
  curves.v.curve_isect = MASQ_CURVE_ROVING;
  curves.v.stats = 1;
  out.push_back(curves);
  NamedVariant shadow{"triangles, any hit, single BLAS, fast", only(&KernelVariant::triangles)};
  shadow.v.any_hit = shadow.v.single_blas = 1;
  shadow.v.robust = 0;
  out.push_back(shadow);
  for (std::int32_t nodes = 1; nodes < 4; ++nodes) {
    NamedVariant n{"node format", {}};
    n.v.node_format = nodes;
    n.v.step_check = 0;
    out.push_back(n);
  }
  return out;
}

TEST(SpirvSpecialize, EveryKernelModuleStaysValidForEveryKindOfVariant) {
  std::vector<std::pair<std::string, std::span<const std::uint32_t>>> modules{
      {"trace", trace_comp_spv},
      {"trace addressed", trace_comp_addr_spv},
      {"trace sized", trace_comp_sized_spv},
      {"rayquery", rayquery_comp_spv},
      {"rt raygen", rtpipeline_rgen_spv},
      {"rt miss", rtpipeline_rmiss_spv},
      {"rt closest", rtpipeline_rchit_spv},
      {"rt intersection", rtpipeline_rint_spv},
      {"rt triangle any", rtpipeline_triangle_rahit_spv},
      {"rt triangle closest", rtpipeline_triangle_rchit_spv},
      // Named one by one: kTraceBvModules (spirv/trace_bv_modules.h) is also defined in
      // masq_vulkan's unity unit, and two definitions of its arrays do not link here.
      {"bv aabb", trace_bv_aabb_sized_spv},
      {"bv sphere", trace_bv_sphere_sized_spv},
      {"bv obb", trace_bv_obb_sized_spv},
      {"bv scb", trace_bv_scb_sized_spv}};
  for (const auto& [name, spirv] : modules) {
    const Decorations before = decorations(spirv);
    for (const NamedVariant& nv : variants()) {
      SCOPED_TRACE(name + ", " + nv.name);
      const std::vector<std::uint32_t> values = spec_constants(nv.v, 64);
      const std::vector<std::uint32_t> frozen = with_constants_frozen(spirv, values);
      EXPECT_EQ(validation_errors(frozen), "");
      const Decorations after = decorations(frozen);
      for (std::uint32_t id : after.spec_ids) EXPECT_GE(id, values.size()) << "constant " << id << " not frozen";
      EXPECT_EQ(after.workgroup_size, before.workgroup_size) << "the work-group size is a decoration's only use";
      EXPECT_LE(frozen.size(), spirv.size());
    }
  }
}

// The point of freezing: a capsule-only trace kernel is a fraction of the module (measured:
// 16,141 of 74,004 words), and a variant that turns more on keeps more.
TEST(SpirvSpecialize, AVariantKeepsOnlyTheCodeItRuns) {
  const std::vector<NamedVariant> vs = variants();
  const std::size_t all = with_constants_frozen(trace_comp_spv, spec_constants(vs[0].v, 64)).size();
  const std::size_t capsules = with_constants_frozen(trace_comp_spv, spec_constants(vs[1].v, 64)).size();
  EXPECT_LT(capsules, std::size(trace_comp_spv) * 2 / 5);
  EXPECT_LT(capsules, all);
}

TEST(SpirvSpecialize, WordsThatAreNoModuleAreOneError) {
  const std::vector<std::uint32_t> junk{0x12345678u, 1, 2, 3, 4, 5};
  const std::vector<std::uint32_t> values{0, 1};
  try {
    with_constants_frozen(junk, values);
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("specialization constants"), std::string::npos) << e.what();
  }
}

// A scene of every primitive type, one instance each, placed apart.
Scene every_type_scene() {
  Scene s;
  s.name = "every type";
  int k = 0;
  for (const PrimTypeRow& row : prim_type_rows) {
    s.geometries.push_back(row.value == PrimType::Triangle
                               ? make_random_mesh(96, 0.5, 11)
                               : make_random_geometry(row.value, 60, 0.004f, 0.03f, 0.5, 21 + k));
    Affine3 at;
    at.translation = glm::dvec3(double(k % 3) - 1.0, double(k / 3) - 0.5, 0.0);
    s.instances.push_back({std::uint32_t(k), at});
    ++k;
  }
  return s;
}

// The first ray whose hit differs in any bit (every field: t, ids, normal, u, v, fault),
// or "".
std::string first_difference(const std::vector<kernel::Hit>& a, const std::vector<kernel::Hit>& b) {
  for (std::size_t i = 0; i < a.size(); ++i)
    if (std::memcmp(&a[i], &b[i], sizeof(kernel::Hit)) != 0)
      return "ray " + std::to_string(i) + ": prim " + std::to_string(a[i].prim) + " t " + std::to_string(a[i].t) +
             " vs prim " + std::to_string(b[i].prim) + " t " + std::to_string(b[i].t);
  return "";
}

TEST(SpirvSpecialize, HostAndDriverSpecializationTraceTheSameBits) {
  const Scene s = every_type_scene();
  const std::vector<kernel::Ray> rays = test::random_rays(5, 3000);
  for (const char* name : {"vulkan", "rayquery", "rtpipeline"}) {
    for (Method m : {Method::Ref, Method::Masq}) {
      const PackedScene ps = build_accel(s, m);
      std::vector<kernel::Hit> hits[2];
      std::vector<kernel::RayStats> stats[2];
      int hit_count = 0;
      for (int driver = 0; driver < 2; ++driver) {
        test::ScopedEnv who("MASQ_VK_SPECIALIZE", driver ? "driver" : "host");
        std::unique_ptr<Backend> be = test::open_or_fail(name, [](const std::string& n) { return make_backend(n); });
        if (!be) return;
        be->set_scene(ps);
        hits[driver].resize(rays.size());
        stats[driver].resize(driver_traversal(name) ? 0 : rays.size());
        be->trace(rays, hits[driver], stats[driver]);
        if (!driver)
          for (const kernel::Hit& h : hits[0]) hit_count += h.prim >= 0;
      }
      SCOPED_TRACE(std::string(name) + " " + method_name(m));
      EXPECT_GT(hit_count, int(rays.size() / 10)) << "too few hits to compare";
      EXPECT_EQ(first_difference(hits[0], hits[1]), "");
      for (std::size_t i = 0; i < stats[0].size(); ++i)
        if (std::memcmp(&stats[0][i], &stats[1][i], sizeof(kernel::RayStats)) != 0) {
          ADD_FAILURE() << "ray " << i << ": the counters differ";
          break;
        }
    }
  }
}

} // namespace
