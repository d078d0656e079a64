// The option name tables (include/masq/names.h) and the backend registry
// (host/registry/backend_registry.cpp): names round-trip, rows follow their enums' order, unknown
// names get one message naming the choices, and the registry's lists and "best" order.
#include "bench/bench_runner.h"
#include "bench/ray_sets.h"
#include "bvh/bv/bv_scene.h"
#include "bvh/options.h"
#include "host/backend.h"
#include "host/device_list.h"
#include "host/device_choice.h"
#include "host/bv_tracer.h"
#include "scenes/scene.h"
#include "stress/stress_cases.h"
#include <gtest/gtest.h>
#include <functional>
#include <map>
#include <set>
#include <string>
#include <vector>

using namespace masq;

namespace {

// Every row's value is its index (the enums are indexed by value: BuildStats'
// auto_candidates, the stress reports' per-kind counts), names are distinct, and each
// name parses back to its value.
template <class Table>
void expect_table_of_enum(const Table& table) {
  SCOPED_TRACE(table.what());
  std::set<std::string> seen;
  for (std::size_t i = 0; i < table.size(); ++i) {
    const auto& r = table.rows()[i];
    EXPECT_EQ(static_cast<std::size_t>(r.value), i) << r.name;
    EXPECT_TRUE(seen.insert(r.name).second) << r.name << " twice";
    EXPECT_NE(std::string(r.help), "") << r.name;
    EXPECT_EQ(table.parse(r.name), r.value);
    EXPECT_STREQ(table.name(r.value), r.name);
  }
  EXPECT_THROW(table.parse("no such name"), Error);
}

std::string message_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

} // namespace

TEST(Names, EveryTableRoundTripsInEnumOrder) {
  expect_table_of_enum(method_table);
  expect_table_of_enum(builder_table);
  expect_table_of_enum(mode_table);
  expect_table_of_enum(node_format_table);
  expect_table_of_enum(curve_obb_table);
  expect_table_of_enum(masq_instances_table);
  expect_table_of_enum(blas_occlusion_table);
  expect_table_of_enum(prim_type_table);
  expect_table_of_enum(bv_type_table);
  expect_table_of_enum(bv_builder_table);
  expect_table_of_enum(ray_set_table);
  expect_table_of_enum(auto_by_table);
  expect_table_of_enum(query_table);
  expect_table_of_enum(stress::ray_kind_table);
  expect_table_of_enum(device_type_table);
  expect_table_of_enum(device_api_table);
}

TEST(Names, UnknownNameNamesTheChoices) {
  EXPECT_EQ(message_of([] { parse_method("bogus"); }), "unknown method 'bogus' (expected ref, masq, cluster or auto)");
  EXPECT_EQ(message_of([] { parse_mode("exact"); }), "unknown mode 'exact' (expected robust or fast)");
  EXPECT_EQ(message_of([] { parse_node_format("w16"); }), "unknown node format 'w16' (expected w4, w8, q8 or o4)");
  EXPECT_EQ(message_of([] { parse_prim_type("cylinder"); }),
            "unknown primitive type 'cylinder' (expected triangle, capsule, round_cone, sphere, curve or ribbon)");
}

TEST(Names, ListsAndHelpComeFromTheRows) {
  EXPECT_EQ(choice_list(std::vector<std::string>{}), "");
  EXPECT_EQ(choice_list(std::vector<std::string>{"a"}), "a");
  EXPECT_EQ(choice_list(std::vector<std::string>{"a", "b", "c"}), "a, b or c");
  EXPECT_EQ(mode_table.names(), (std::vector<std::string>{"robust", "fast"}));
  EXPECT_EQ(mode_table.help(),
            std::string("robust (") + api::mode_rows[0].help + ") or fast (" + api::mode_rows[1].help + ")");
  auto strands = [](const PrimTypeRow& r) { return r.value != PrimType::Triangle; };
  EXPECT_EQ(prim_type_table.choices(strands), "capsule, round_cone, sphere, curve or ribbon");
  EXPECT_EQ(all_builders(), builder_table.values());
  // The names messages and files used before the tables.
  EXPECT_STREQ(prim_type_name(PrimType::RoundCone), "round_cone");
  EXPECT_STREQ(prim_type_key(PrimType::RoundCone), "round_cone");
  EXPECT_EQ(parse_prim_type("cone"), PrimType::RoundCone); // the older name, still typed in scene files
  EXPECT_EQ(parse_prim_type("round_cone"), PrimType::RoundCone);
  EXPECT_STREQ(stress::ray_kind_name(stress::RayKind::Invalid), "nan/inf");
}

// The builder's parts, as bvh/binary/builder.cpp and bvh/twolevel/build_accel.cpp read them.
TEST(Names, BuilderColumns) {
  for (Builder b : all_builders()) {
    SCOPED_TRACE(builder_name(b));
    EXPECT_EQ(builder_splits(b), b == Builder::Sbvh || b == Builder::SbvhReinsert);
    EXPECT_EQ(builder_reinserts(b), b == Builder::SahReinsert || b == Builder::SbvhReinsert);
    EXPECT_EQ(builder_leaf_block(b), b == Builder::Sah4 ? 4 : 1);
    EXPECT_EQ(builder_prices_isect(b), b == Builder::SahPriced);
  }
}

// "best" is the best real device: a GPU backend whose device runs on the host's cores
// (lavapipe, PoCL's CPU device) comes after the cpu backend, a real GPU's before it
// (issue 40). Checked against the device list's own picks and types.
TEST(BackendRegistry, BestPutsDevicesOnTheHostsCoresAfterCpu) {
  const std::vector<std::string> order = best_backend_order();
  std::vector<std::string> ranked;
  for (const BackendRow& r : backend_table.rows())
    if (r.best_rank > 0) ranked.push_back(r.name);
  EXPECT_TRUE(std::is_permutation(order.begin(), order.end(), ranked.begin(), ranked.end()));
  const auto cpu = std::find(order.begin(), order.end(), "cpu");
  ASSERT_NE(cpu, order.end());
  for (const ApiDevices& a : list_devices())
    for (const auto& [backend, choice] : a.picks) {
      const auto at = std::find(order.begin(), order.end(), backend);
      if (at == order.end() || choice.position < 0) continue;
      const bool host_cores = a.devices.at(std::size_t(choice.position)).type == DeviceType::Cpu;
      EXPECT_EQ(at > cpu, host_cores) << backend << " on " << a.devices.at(std::size_t(choice.position)).name;
    }
}

TEST(BackendRegistry, OneTableForEveryList) {
  EXPECT_EQ(backend_names(), (std::vector<std::string>{"cpu", "vulkan", "opencl", "rayquery", "rtpipeline"}));
  EXPECT_EQ(bv_backend_names(), (std::vector<std::string>{"cpu", "vulkan", "opencl"}));
  // best_rank: vulkan, then opencl, then cpu; never the driver-traversal backends (and
  // best_backend_order moves a GPU backend on the host's cores after cpu).
  std::map<int, std::string> best;
  for (const BackendRow& r : backend_table.rows())
    if (r.best_rank > 0) best[r.best_rank] = r.name;
  EXPECT_EQ(best, (std::map<int, std::string>{{1, "vulkan"}, {2, "opencl"}, {3, "cpu"}}));
  EXPECT_EQ(message_of([] { make_backend("bogus"); }),
            "unknown backend 'bogus' (expected cpu, vulkan, opencl, rayquery or rtpipeline)");
  EXPECT_EQ(message_of([] { make_bv_tracer("rayquery"); }),
            "unknown bv backend 'rayquery' (expected cpu, vulkan or opencl)");
  EXPECT_EQ(make_backend("cpu")->name(), "cpu");
  EXPECT_EQ(make_bv_tracer("cpu")->name(), "cpu");
  // Each device selector picks the device of exactly one backend; cpu has none.
  std::map<std::string, std::string> api_of;
  for (const BackendRow& r : backend_table.rows())
    if (r.device_api) {
      EXPECT_NE(device_api_table.find(r.device_api), nullptr) << r.name;
      EXPECT_TRUE(api_of.emplace(r.device_api, r.name).second) << r.device_api << " twice";
    }
  EXPECT_EQ(api_of.size(), device_api_table.size());
  EXPECT_EQ(backend_table.at("cpu").device_api, nullptr);
}
