// Device choice (host/device_choice.h): ranking, index and name selectors, the error of a
// selector that names nothing, rayquery and rtpipeline on the vulkan backend's device, and --device's
// syntax, on devices given as data (what real drivers report); then the same through
// the real drivers of this machine (lavapipe, PoCL).
#include "host/backend.h"
#include "host/device_choice.h"
#include "host/device_list.h"
#include "test_env.h"
#include <gtest/gtest.h>
#include <cctype>

namespace masq {
namespace {

DeviceInfo dev(int index, const char* name, DeviceType type, std::string no_ray_query = "",
               std::string unusable = "", std::string no_ray_pipeline = "") {
  DeviceInfo d;
  d.index = index;
  d.name = name;
  d.type = type;
  d.no_ray_query = std::move(no_ray_query);
  d.unusable = std::move(unusable);
  d.no_ray_pipeline = std::move(no_ray_pipeline);
  return d;
}

// A GPU machine with lavapipe installed, in the order a loader may enumerate them. The
// H100's driver has ray-tracing pipelines but no ray query.
std::vector<DeviceInfo> gpu_machine() {
  return {dev(0, "llvmpipe (LLVM 15.0.6, 256 bits)", DeviceType::Cpu),
          dev(1, "Intel(R) UHD Graphics 770", DeviceType::Integrated, "lacks VK_KHR_ray_query", "",
              "lacks VK_KHR_ray_tracing_pipeline"),
          dev(2, "NVIDIA H100 80GB HBM3", DeviceType::Discrete, "lacks VK_KHR_ray_query"),
          dev(3, "Virtio-GPU Venus", DeviceType::Virtual, "lacks VK_KHR_acceleration_structure", "",
              "lacks VK_KHR_acceleration_structure")};
}

DeviceChoice choose_ray_query_device(const std::vector<DeviceInfo>& d, const DeviceSelector& vulkan,
                                     const DeviceSelector& own) {
  return choose_traversal_device(d, vulkan, own, DeviceNeed::RayQuery, DeviceApi::RayQuery);
}

DeviceSelector sel(std::string value) { return {std::move(value), "MASQ_VK_DEVICE"}; }

int pick(const std::vector<DeviceInfo>& d, const std::string& s, DeviceNeed need = DeviceNeed::Compute) {
  return choose_device(d, sel(s), "Vulkan", need).position;
}

TEST(DeviceChoice, RanksDiscreteIntegratedVirtualCpu) {
  EXPECT_EQ(ranked_devices(gpu_machine()), (std::vector<std::size_t>{2, 1, 3, 0}));
  EXPECT_LT(device_rank(DeviceType::Discrete), device_rank(DeviceType::Integrated));
  EXPECT_LT(device_rank(DeviceType::Integrated), device_rank(DeviceType::Virtual));
  EXPECT_LT(device_rank(DeviceType::Virtual), device_rank(DeviceType::Cpu));
  EXPECT_EQ(pick(gpu_machine(), ""), 2);
}

TEST(DeviceChoice, OpenClRanksGpuAcceleratorCpu) {
  // OpenCL GPUs enter as discrete or integrated (CL_DEVICE_HOST_UNIFIED_MEMORY).
  std::vector<DeviceInfo> cl = {dev(0, "pthread-haswell-AMD EPYC 7B13", DeviceType::Cpu),
                                dev(1, "Xilinx U250", DeviceType::Accelerator),
                                dev(2, "gfx1030", DeviceType::Discrete)};
  EXPECT_EQ(ranked_devices(cl), (std::vector<std::size_t>{2, 1, 0}));
  cl.pop_back();
  EXPECT_EQ(choose_device(cl, {}, "OpenCL", DeviceNeed::Compute).position, 1);
}

TEST(DeviceChoice, TiesKeepEnumerationOrder) {
  std::vector<DeviceInfo> two = {dev(0, "llvmpipe", DeviceType::Cpu), dev(1, "NVIDIA A", DeviceType::Discrete),
                                 dev(2, "NVIDIA B", DeviceType::Discrete)};
  EXPECT_EQ(ranked_devices(two), (std::vector<std::size_t>{1, 2, 0}));
  EXPECT_EQ(pick(two, "nvidia"), 1); // a substring naming several: the best-ranked, then the first
}

TEST(DeviceChoice, IndexSelectors) {
  EXPECT_EQ(pick(gpu_machine(), "0"), 0);
  EXPECT_EQ(pick(gpu_machine(), "3"), 3);
  // Indices are the enumeration's (what masq info shows), not the ranking's.
  std::vector<DeviceInfo> shuffled = {gpu_machine()[2], gpu_machine()[0]};
  EXPECT_EQ(pick(shuffled, "0"), 1);
}

TEST(DeviceChoice, NameSelectorsIgnoreCase) {
  EXPECT_EQ(pick(gpu_machine(), "llvmpipe"), 0);
  EXPECT_EQ(pick(gpu_machine(), "LLVMPIPE"), 0);
  EXPECT_EQ(pick(gpu_machine(), "h100"), 2);
  EXPECT_EQ(pick(gpu_machine(), "uhd graphics"), 1);
  EXPECT_EQ(pick(gpu_machine(), "256 bits"), 0);
}

TEST(DeviceChoice, SelectorNamingNothingIsAnErrorListingTheDevices) {
  for (const std::string s : {"no-such-gpu", "7", "99999999999999"}) {
    try {
      choose_device(gpu_machine(), sel(s), "Vulkan", DeviceNeed::Compute);
      ADD_FAILURE() << s << " matched a device";
    } catch (const BackendUnavailable&) {
      ADD_FAILURE() << "a selector naming nothing is an error, not an unavailable backend";
    } catch (const Error& e) {
      const std::string msg = e.what();
      EXPECT_NE(msg.find("MASQ_VK_DEVICE='" + s + "'"), std::string::npos) << msg;
      EXPECT_NE(msg.find("Vulkan"), std::string::npos) << msg;
      for (const DeviceInfo& d : gpu_machine()) EXPECT_NE(msg.find(d.name), std::string::npos) << msg;
      EXPECT_NE(msg.find("2 'NVIDIA H100 80GB HBM3' (discrete GPU)"), std::string::npos) << msg;
      EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
    }
  }
  EXPECT_THROW(choose_device({}, sel("0"), "Vulkan", DeviceNeed::Compute), Error);
}

TEST(DeviceChoice, UnusableDevicesAreSkippedOrNamed) {
  std::vector<DeviceInfo> d = gpu_machine();
  d[2].unusable = "is older than Vulkan 1.2";
  EXPECT_EQ(pick(d, ""), 1); // the best usable one
  DeviceChoice c = choose_device(d, sel("nvidia"), "Vulkan", DeviceNeed::Compute);
  EXPECT_EQ(c.position, -1); // named, but cannot run the kernels: said so, no other device taken
  EXPECT_EQ(c.why, "device 'NVIDIA H100 80GB HBM3' is older than Vulkan 1.2");
  EXPECT_EQ(choose_device({}, {}, "Vulkan", DeviceNeed::Compute).why, "no Vulkan device");
}

TEST(DeviceChoice, RayQueryFollowsTheVulkanDevice) {
  const std::vector<DeviceInfo> d = gpu_machine();
  // vulkan takes the H100, which lacks ray query: rayquery is unavailable, naming it,
  // and does not fall back to llvmpipe.
  DeviceChoice c = choose_ray_query_device(d, {}, {});
  EXPECT_EQ(c.position, -1);
  EXPECT_NE(c.why.find("'NVIDIA H100 80GB HBM3' lacks VK_KHR_ray_query"), std::string::npos) << c.why;
  EXPECT_NE(c.why.find("MASQ_RQ_DEVICE"), std::string::npos) << c.why;
  // The vulkan selector moves both.
  EXPECT_EQ(choose_ray_query_device(d, sel("llvmpipe"), {}).position, 0);
  // Told otherwise: rayquery's own selector.
  EXPECT_EQ(choose_ray_query_device(d, {}, {"llvmpipe", "MASQ_RQ_DEVICE"}).position, 0);
  EXPECT_EQ(choose_ray_query_device(d, {}, {"intel", "MASQ_RQ_DEVICE"}).position, -1);
  EXPECT_THROW(choose_ray_query_device(d, {}, {"no-such-gpu", "MASQ_RQ_DEVICE"}), Error);
  // Where the vulkan device has ray query, both take it.
  std::vector<DeviceInfo> rt = d;
  rt[2].no_ray_query.clear();
  EXPECT_EQ(choose_ray_query_device(rt, {}, {}).position, 2);
  EXPECT_EQ(choose_device(rt, {}, "Vulkan", DeviceNeed::RayQuery).position, 2);
}

// The H100 lacks ray query but has the ray-tracing pipeline: rtpipeline runs there, on
// the vulkan backend's device, and says why where it cannot.
TEST(DeviceChoice, RtPipelineFollowsTheVulkanDevice) {
  const std::vector<DeviceInfo> d = gpu_machine();
  auto choose = [&](const DeviceSelector& vulkan, const DeviceSelector& own) {
    return choose_traversal_device(d, vulkan, own, DeviceNeed::RayPipeline, DeviceApi::RtPipeline);
  };
  EXPECT_EQ(choose({}, {}).position, 2);
  DeviceChoice c = choose(sel("intel"), {});
  EXPECT_EQ(c.position, -1);
  EXPECT_NE(c.why.find("'Intel(R) UHD Graphics 770' lacks VK_KHR_ray_tracing_pipeline"), std::string::npos) << c.why;
  EXPECT_NE(c.why.find("rtpipeline runs on the vulkan backend's device; MASQ_RT_DEVICE names another"),
            std::string::npos)
      << c.why;
  EXPECT_EQ(choose(sel("intel"), {"llvmpipe", "MASQ_RT_DEVICE"}).position, 0);
  EXPECT_EQ(choose({}, {"venus", "MASQ_RT_DEVICE"}).position, -1);
  EXPECT_THROW(choose({}, {"no-such-gpu", "MASQ_RT_DEVICE"}), Error);
  EXPECT_EQ(parse_device_option("rtpipeline=1"), (std::vector<std::pair<DeviceApi, std::string>>{
                                                     {DeviceApi::RtPipeline, "1"}}));
}

TEST(DeviceChoice, DeviceOptionSyntax) {
  using P = std::vector<std::pair<DeviceApi, std::string>>;
  EXPECT_EQ(parse_device_option("nvidia"), (P{{DeviceApi::Vulkan, "nvidia"}, {DeviceApi::OpenCl, "nvidia"}}));
  EXPECT_EQ(parse_device_option("vulkan=1,opencl=pocl"), (P{{DeviceApi::Vulkan, "1"}, {DeviceApi::OpenCl, "pocl"}}));
  EXPECT_EQ(parse_device_option("rayquery=llvmpipe"), (P{{DeviceApi::RayQuery, "llvmpipe"}}));
  EXPECT_EQ(parse_device_option("vulkan=llvmpipe (LLVM 15.0.6, 256 bits),opencl=0"),
            (P{{DeviceApi::Vulkan, "llvmpipe (LLVM 15.0.6, 256 bits)"}, {DeviceApi::OpenCl, "0"}}));
  for (const char* bad : {"", "metal=1", "vulkan=", "vulkan=1,vulkan=2", "vulkan=1,opencl="}) {
    try {
      parse_device_option(bad);
      ADD_FAILURE() << "'" << bad << "' parsed";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(std::string("--device '") + bad + "'"), std::string::npos) << e.what();
    }
  }
}

TEST(DeviceChoice, OverrideBeforeEnvironment) {
  ::setenv("MASQ_CL_DEVICE", "from-env", 1);
  EXPECT_EQ(device_selector(DeviceApi::OpenCl).value, "from-env");
  EXPECT_EQ(device_selector(DeviceApi::OpenCl).source, "MASQ_CL_DEVICE");
  set_device_selector(DeviceApi::OpenCl, "from-cli", "--device");
  EXPECT_EQ(device_selector(DeviceApi::OpenCl).value, "from-cli");
  EXPECT_EQ(device_selector(DeviceApi::OpenCl).source, "--device");
  set_device_selector(DeviceApi::OpenCl, "", "");
  EXPECT_EQ(device_selector(DeviceApi::OpenCl).value, "from-env");
  ::unsetenv("MASQ_CL_DEVICE");
  EXPECT_TRUE(device_selector(DeviceApi::OpenCl).empty());
}

// The real drivers: every device listed, each backend's pick among them, and the
// selectors honoured when the backends open.
class RealDevices : public ::testing::Test {
 protected:
  void TearDown() override {
    for (DeviceApi a : device_api_table.values()) set_device_selector(a, "", "");
  }
};

TEST_F(RealDevices, ListingAndPicks) {
  for (const ApiDevices& a : list_devices()) {
    if (!a.unavailable.empty()) {
      if (!test::missing_backends_allowed()) ADD_FAILURE() << a.unavailable;
      continue;
    }
    ASSERT_FALSE(a.devices.empty()) << a.api;
    for (std::size_t i = 0; i < a.devices.size(); ++i) {
      EXPECT_EQ(a.devices[i].index, static_cast<int>(i));
      EXPECT_FALSE(a.devices[i].name.empty());
      EXPECT_GT(a.devices[i].memory_bytes, 0u) << a.devices[i].name;
      EXPECT_FALSE(a.devices[i].subgroup_source.empty());
    }
    for (const auto& [backend, choice] : a.picks) {
      if (choice.position >= 0) continue;
      // No listed device serves this backend (ray query on a GPU without VK_KHR_ray_query,
      // as on an H100/H200): allowed where missing backends are, and it must say why.
      EXPECT_FALSE(choice.why.empty()) << backend;
      if (!test::missing_backends_allowed()) ADD_FAILURE() << backend << ": " << choice.why;
    }
  }
}

TEST_F(RealDevices, SelectorsReachTheBackends) {
  for (const BackendRow& row : backend_table.rows()) {
    if (!row.device_api) continue;
    const std::string name = row.name;
    auto be = test::open_or_fail(name, [](const std::string& n) { return make_backend(n); });
    if (!be) continue;
    const std::string device = be->device_name();
    be.reset();
    const DeviceApi api = device_api_table.parse(backend_table.at(name).device_api);
    // Index 0 and the first word of the device's name in capitals both name a device here.
    std::string word = device.substr(0, device.find(' '));
    for (char& ch : word) ch = static_cast<char>(std::toupper(static_cast<unsigned char>(ch)));
    for (const std::string& s : {std::string("0"), word}) {
      set_device_selector(api, s, "--device");
      EXPECT_NO_THROW(make_backend(name)) << name << " with selector '" << s << "'";
    }
    set_device_selector(api, "no-such-gpu", "--device");
    try {
      make_backend(name);
      ADD_FAILURE() << name << " opened with selector no-such-gpu";
    } catch (const BackendUnavailable& e) {
      ADD_FAILURE() << "an unavailable backend instead of an error: " << e.what();
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("--device='no-such-gpu'"), std::string::npos) << e.what();
    }
    const std::vector<std::string> run{name};
    EXPECT_THROW(check_device_selectors(run), Error);
    set_device_selector(api, "", "");
    EXPECT_NO_THROW(check_device_selectors(run));
  }
}

TEST_F(RealDevices, DriverTraversalOnTheVulkanDevice) {
  auto vk = test::open_or_fail("vulkan", [](const std::string& n) { return make_backend(n); });
  for (const char* name : {"rayquery", "rtpipeline"}) {
    auto be = test::open_or_fail(name, [](const std::string& n) { return make_backend(n); });
    if (vk && be) {
      EXPECT_EQ(vk->device_name(), be->device_name()) << name;
    }
  }
}

} // namespace
} // namespace masq
