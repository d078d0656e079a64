// GLSL std430 must lay out every GPU struct of kernels/layout.h exactly as C++ does.
// tests/kernels/layout_roundtrip.comp loads each struct type through the struct and writes its
// fields in declaration order as 32-bit words, and assembles structs field by field
// from words; both must reproduce the C++ bytes (every field is a 4-byte scalar, so a
// C++ struct's bytes ARE its fields in declaration order; static asserts in layout.h
// check there is no padding). Vulkan missing fails the test (scripts/setup.sh installs
// lavapipe) unless MASQ_ALLOW_MISSING_BACKENDS=1.
#include "host/backend.h"
#include "host/vulkan/vk_pipeline.h"
#include "kernels/layout.h"
#include "spirv/layout_roundtrip_comp_spv.h"

#include <gtest/gtest.h>

#include <bit>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>
#include "tests/test_env.h"

namespace {

using namespace masq;
using namespace masq::kernel;

constexpr std::uint32_t kCount = 37; // not a multiple of the work-group size

struct Section {
  const char* name;
  std::size_t bytes; // sizeof the struct
};
// In binding order (0..17 in, 20..37 out) and flat-section order of the kernel.
const Section kSections[] = {
    {"WideNode", sizeof(WideNode)},   {"Instance", sizeof(Instance)}, {"Frame", sizeof(Frame)},
    {"Geometry", sizeof(Geometry)},   {"Triangle", sizeof(Triangle)}, {"Capsule", sizeof(Capsule)},
    {"RoundCone", sizeof(RoundCone)}, {"Sphere", sizeof(Sphere)},     {"Curve", sizeof(Curve)},
    {"Ray", sizeof(Ray)},             {"Hit", sizeof(Hit)},           {"RayStats", sizeof(RayStats)},
    {"TraceParams", sizeof(TraceParams)}, {"WideNode8", sizeof(WideNode8)},   {"QuantNode8", sizeof(QuantNode8)},
    {"MasqInstance", sizeof(MasqInstance)}, {"MasqOwner", sizeof(MasqOwner)}, {"Ribbon", sizeof(Ribbon)},
};
constexpr std::size_t kTypes = std::size(kSections);
static_assert(kTypes == 18);
// Bindings of layout_roundtrip.comp: In0..In17, FlatOut, FlatIn, Out0..Out17.
constexpr std::uint32_t kFlatOutBinding = kTypes;
constexpr std::uint32_t kFlatInBinding = kTypes + 1;
constexpr std::uint32_t kOutBinding0 = kTypes + 2;
constexpr std::uint32_t kBindings = 2 * kTypes + 2;
static_assert(kBindings == 38);

// Distinct words that survive a float round trip (normal floats) and an int one.
std::uint32_t word(std::uint32_t k, bool negative) {
  float f = static_cast<float>(k + 1) * (negative ? -0.5f : 1.0f);
  return std::bit_cast<std::uint32_t>(f);
}

bool allow_no_vulkan() { return masq::test::missing_backends_allowed(); }

TEST(GlslLayout, Std430MatchesCpp) {
  std::shared_ptr<vk::Context> ctx;
  try {
    ctx = vk::Context::get("vulkan");
  } catch (const BackendUnavailable& e) {
    if (allow_no_vulkan()) GTEST_SKIP() << e.what() << " (MASQ_ALLOW_MISSING_BACKENDS=1)";
    FAIL() << e.what() << " (scripts/setup.sh installs lavapipe; MASQ_ALLOW_MISSING_BACKENDS=1 skips)";
  }

  // Inputs: structs (as words) and the flat words, with disjoint values.
  std::vector<std::vector<std::uint32_t>> in_structs(kTypes);
  std::vector<std::uint32_t> flat_in;
  std::uint32_t counter = 0;
  for (std::size_t k = 0; k < kTypes; ++k) {
    for (std::size_t w = 0; w < kCount * kSections[k].bytes / 4; ++w) {
      in_structs[k].push_back(word(counter, false));
      flat_in.push_back(word(counter, true));
      ++counter;
    }
  }

  std::vector<VkDescriptorType> types(kBindings, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER);
  vk::KernelLayout layout(*ctx, types, sizeof(std::uint32_t));
  std::vector<vk::Buffer> in_bufs, out_bufs;
  for (std::size_t k = 0; k < kTypes; ++k) {
    in_bufs.emplace_back(*ctx, in_structs[k].size() * 4, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
    in_bufs.back().upload(in_structs[k].data(), in_structs[k].size() * 4);
    layout.bind_buffer(static_cast<std::uint32_t>(k), in_bufs.back());
    out_bufs.emplace_back(*ctx, in_structs[k].size() * 4, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
    std::vector<std::uint32_t> zeros(in_structs[k].size(), 0u);
    out_bufs.back().upload(zeros.data(), zeros.size() * 4);
    layout.bind_buffer(kOutBinding0 + static_cast<std::uint32_t>(k), out_bufs.back());
  }
  vk::Buffer flat_out_buf(*ctx, flat_in.size() * 4, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
  std::vector<std::uint32_t> zeros(flat_in.size(), 0u);
  flat_out_buf.upload(zeros.data(), zeros.size() * 4);
  vk::Buffer flat_in_buf(*ctx, flat_in.size() * 4, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
  flat_in_buf.upload(flat_in.data(), flat_in.size() * 4);
  layout.bind_buffer(kFlatOutBinding, flat_out_buf);
  layout.bind_buffer(kFlatInBinding, flat_in_buf);

  vk::DeviceOwned<VkPipeline> pipeline = layout.create_pipeline(layout_roundtrip_comp_spv, {});
  const std::uint32_t n = kCount;
  layout.dispatch(pipeline.get(), &n, (kCount + 63) / 64);

  std::vector<std::uint32_t> flat_out(flat_in.size());
  flat_out_buf.download(flat_out.data(), flat_out.size() * 4);
  std::size_t base = 0;
  for (std::size_t k = 0; k < kTypes; ++k) {
    const std::size_t words = kSections[k].bytes / 4;
    // struct -> words: GLSL's field reads must find the C++ bytes.
    int bad = 0;
    for (std::size_t w = 0; w < kCount * words; ++w)
      if (flat_out[base + w] != in_structs[k][w] && bad++ < 3)
        ADD_FAILURE() << kSections[k].name << " element " << w / words << " word " << w % words
                      << ": GLSL read 0x" << std::hex << flat_out[base + w] << ", C++ wrote 0x"
                      << in_structs[k][w];
    EXPECT_EQ(bad, 0) << kSections[k].name << ": GLSL reads disagree with the C++ layout";
    // words -> struct: GLSL's field writes must land at the C++ offsets.
    std::vector<std::uint32_t> got(kCount * words);
    out_bufs[k].download(got.data(), got.size() * 4);
    EXPECT_EQ(0, std::memcmp(got.data(), flat_in.data() + base, got.size() * 4))
        << kSections[k].name << ": GLSL writes disagree with the C++ layout";
    base += kCount * words;
  }
}

} // namespace
