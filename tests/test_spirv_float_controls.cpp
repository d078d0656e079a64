// The device-dependent shader setup of the Vulkan backends (host/vulkan/vk_shader_limits.h):
// SignedZeroInfNanPreserve and NoContraction patched into the kernels' SPIR-V (checked by
// spirv-val and by creating the pipelines under validation on this machine's device; that
// the backends then return the cpu's bits: tests/test_cross_backend_bits.cpp), and the work-group
// size fitted to the subgroup size and the device limits, for the limits of real devices
// given as data.
#include "host/vulkan/spirv_float_controls.h"
#include "host/vulkan/vk_shader_limits.h"
#include "masq/error.h"
#include "spirv/rayquery_comp_spv.h"
#include "spirv/trace_comp_spv.h"
#include "spirv/trace_bv_modules.h"
#include "tests/test_env.h"
#include <gtest/gtest.h>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <unistd.h>

using namespace masq;
using namespace masq::vk;

namespace {

constexpr std::uint32_t kCapability = 4466, kMode = 4461;

struct Found {
  int capabilities = 0, modes = 0, entries = 0, extensions = 0;
};

Found scan(const std::vector<std::uint32_t>& m) {
  Found f;
  for (std::size_t at = 5; at < m.size(); at += m[at] >> 16) {
    const std::uint32_t op = m[at] & 0xffff;
    if (op == 17 && m[at + 1] == kCapability) ++f.capabilities;
    if (op == 16 && m[at + 2] == kMode && m[at + 3] == 32) ++f.modes;
    if (op == 15) ++f.entries;
    if (op == 10 && std::strncmp(reinterpret_cast<const char*>(&m[at + 1]), "SPV_KHR_float_controls", 23) == 0)
      ++f.extensions;
  }
  return f;
}

// spirv-val's verdict on the module (the one the build validates the kernels with).
std::string validate(const std::vector<std::uint32_t>& m, const char* env) {
  const std::filesystem::path file =
      std::filesystem::temp_directory_path() / ("masq_float_controls_" + std::to_string(::getpid()) + ".spv");
  {
    std::ofstream out(file, std::ios::binary);
    out.write(reinterpret_cast<const char*>(m.data()), std::streamsize(m.size() * 4));
  }
  const std::string cmd = std::string(MASQ_SPIRV_VAL) + " --target-env " + env + " " + file.string() + " 2>&1";
  std::string log;
  FILE* p = popen(cmd.c_str(), "r");
  char buf[256];
  while (p && std::fgets(buf, sizeof(buf), p)) log += buf;
  const int rc = p ? pclose(p) : -1;
  std::filesystem::remove(file);
  return rc == 0 ? "" : "spirv-val failed: " + log;
}

std::vector<std::uint32_t> words(std::span<const std::uint32_t> s) { return {s.begin(), s.end()}; }

TEST(SpirvFloatControls, EveryKernelModuleGetsTheModeAndStaysValid) {
  std::vector<std::pair<std::string, std::vector<std::uint32_t>>> modules{{"trace", words(trace_comp_spv)},
                                                                          {"rayquery", words(rayquery_comp_spv)}};
  for (const TraceBvModule& m : kTraceBvModules) modules.push_back({"bv " + std::to_string(m.bv_type), words(m.bound)});
  for (const auto& [name, spirv] : modules) {
    SCOPED_TRACE(name);
    ASSERT_EQ(scan(spirv).capabilities, 0);
    const std::vector<std::uint32_t> patched = with_signed_zero_inf_nan_preserve(spirv);
    const Found f = scan(patched);
    EXPECT_EQ(f.capabilities, 1);
    EXPECT_EQ(f.modes, f.entries);
    EXPECT_GE(f.entries, 1);
    EXPECT_EQ(f.extensions, spirv[1] < 0x10400 ? 1 : 0);
    EXPECT_EQ(validate(patched, "vulkan1.2"), "");
    EXPECT_EQ(with_signed_zero_inf_nan_preserve(patched), patched) << "patching twice adds nothing";
  }
}

// A SPIR-V 1.3 module (Vulkan 1.1) needs the extension for the mode: the smallest
// compute shader, assembled here word by word.
TEST(SpirvFloatControls, OlderModulesGetTheExtension) {
  auto op = [](std::uint32_t n, std::uint32_t code) { return n << 16 | code; };
  const std::vector<std::uint32_t> m{
      0x07230203, 0x00010300, 0, 5, 0,
      op(2, 17), 1,                                  // OpCapability Shader
      op(3, 14), 0, 1,                               // OpMemoryModel Logical GLSL450
      op(5, 15), 5, 1, 0x6e69616d, 0,                // OpEntryPoint GLCompute %1 "main"
      op(6, 16), 1, 17, 1, 1, 1,                     // OpExecutionMode %1 LocalSize 1 1 1
      op(2, 19), 2,                                  // %2 = OpTypeVoid
      op(3, 33), 3, 2,                               // %3 = OpTypeFunction %2
      op(5, 54), 2, 1, 0, 3,                         // %1 = OpFunction %2 None %3
      op(2, 248), 4,                                 // %4 = OpLabel
      op(1, 253),                                    // OpReturn
      op(1, 56)};                                    // OpFunctionEnd
  ASSERT_EQ(validate(m, "vulkan1.1"), "");
  const std::vector<std::uint32_t> patched = with_signed_zero_inf_nan_preserve(m);
  const Found f = scan(patched);
  EXPECT_EQ(f.capabilities, 1);
  EXPECT_EQ(f.extensions, 1);
  EXPECT_EQ(f.modes, 1);
  EXPECT_EQ(validate(patched, "vulkan1.1"), "");
}

// Float results (float arithmetic, GLSL.std.450 instructions with a float result) with
// and without NoContraction, read from the module independently of the pass. Opcodes and
// enumerants of the SPIR-V specification.
struct Contraction {
  int decorated = 0, undecorated = 0, fma = 0, fma_decorated = 0, duplicates = 0;
};

Contraction scan_contraction(const std::vector<std::uint32_t>& m) {
  std::map<std::uint32_t, int> decorations; // id -> NoContraction decorations on it
  std::set<std::uint32_t> floats;
  std::vector<std::pair<std::uint32_t, bool>> results; // (id, is a GLSL.std.450 Fma)
  std::uint32_t glsl = 0;
  for (std::size_t at = 5; at < m.size(); at += m[at] >> 16) {
    const std::uint32_t op = m[at] & 0xffff;
    if (op == 11 && std::strcmp(reinterpret_cast<const char*>(&m[at + 2]), "GLSL.std.450") == 0) glsl = m[at + 1];
    if (op == 71 && m[at + 2] == 42) ++decorations[m[at + 1]];
    if (op == 22) floats.insert(m[at + 1]);
    if ((op == 23 || op == 24) && floats.count(m[at + 2])) floats.insert(m[at + 1]);
    const bool arithmetic = op == 127 || op == 129 || op == 131 || op == 133 || op == 136 || op == 140 || op == 141 ||
                            (op >= 142 && op <= 148);
    if (arithmetic || (op == 12 && m[at + 3] == glsl && floats.count(m[at + 1])))
      results.push_back({m[at + 2], op == 12 && m[at + 4] == 50});
  }
  Contraction c;
  for (const auto& [id, fma] : results) {
    const int n = decorations.count(id) ? decorations[id] : 0;
    (n > 0 ? c.decorated : c.undecorated) += 1;
    c.duplicates += n > 1 ? 1 : 0;
    c.fma += fma ? 1 : 0;
    c.fma_decorated += fma && n > 0 ? 1 : 0;
  }
  return c;
}

// Every float operation of every kernel module NoContraction after the pass, the module
// still valid, alone and with the float-controls mode. glslang decorates only what
// `precise` marks (nothing: the kernels carry none) and never an Fma instruction.
TEST(SpirvNoContraction, EveryFloatOperationOfEveryKernelModule) {
  std::vector<std::pair<std::string, std::vector<std::uint32_t>>> modules{{"trace", words(trace_comp_spv)},
                                                                          {"rayquery", words(rayquery_comp_spv)}};
  for (const TraceBvModule& m : kTraceBvModules) modules.push_back({"bv " + std::to_string(m.bv_type), words(m.bound)});
  for (const auto& [name, spirv] : modules) {
    SCOPED_TRACE(name);
    const Contraction before = scan_contraction(spirv);
    EXPECT_GT(before.undecorated, 0) << "glslang already decorates everything: the pass has nothing to prove";
    const std::vector<std::uint32_t> patched = with_no_contraction(spirv);
    const Contraction after = scan_contraction(patched);
    EXPECT_EQ(after.undecorated, 0);
    EXPECT_EQ(after.duplicates, 0);
    EXPECT_EQ(after.decorated, before.decorated + before.undecorated);
    EXPECT_EQ(after.fma_decorated, after.fma);
    EXPECT_EQ(patched.size(), spirv.size() + 3 * std::size_t(before.undecorated));
    EXPECT_EQ(validate(patched, "vulkan1.2"), "");
    EXPECT_EQ(validate(with_signed_zero_inf_nan_preserve(patched), "vulkan1.2"), "");
    EXPECT_EQ(with_no_contraction(patched), patched) << "patching twice adds nothing";
    std::printf("%s: %d float results, %d decorated by glslang (%d Fma)\n", name.c_str(), after.decorated,
                before.decorated, after.fma);
  }
}

// A module assembled word by word: a float product, an Fma, a vector dot product and an
// integer sum. The float results get the decoration, the integer one does not, and a
// result glslang already decorated is not decorated twice.
TEST(SpirvNoContraction, FloatResultsOnlyAndOnce) {
  auto op = [](std::uint32_t n, std::uint32_t code) { return n << 16 | code; };
  const std::vector<std::uint32_t> m{
      0x07230203, 0x00010500, 0, 20, 0,
      op(2, 17), 1,                                            // OpCapability Shader
      op(6, 11), 2, 0x4c534c47, 0x6474732e, 0x3035342e, 0,     // %2 = OpExtInstImport "GLSL.std.450"
      op(3, 14), 0, 1,                                         // OpMemoryModel Logical GLSL450
      op(5, 15), 5, 1, 0x6e69616d, 0,                          // OpEntryPoint GLCompute %1 "main"
      op(6, 16), 1, 17, 1, 1, 1,                               // OpExecutionMode %1 LocalSize 1 1 1
      op(3, 71), 10, 42,                                       // OpDecorate %10 NoContraction (as by `precise`)
      op(2, 19), 3,                                            // %3 = OpTypeVoid
      op(3, 33), 4, 3,                                         // %4 = OpTypeFunction %3
      op(3, 22), 5, 32,                                        // %5 = OpTypeFloat 32
      op(4, 21), 6, 32, 1,                                     // %6 = OpTypeInt 32 1
      op(4, 23), 7, 5, 3,                                      // %7 = OpTypeVector %5 3
      op(4, 43), 5, 8, 0x3f800000,                             // %8 = OpConstant %5 1.0
      op(4, 43), 6, 9, 3,                                      // %9 = OpConstant %6 3
      op(6, 44), 7, 15, 8, 8, 8,                               // %15 = OpConstantComposite %7 %8 %8 %8
      op(5, 54), 3, 1, 0, 4,                                   // %1 = OpFunction %3 None %4
      op(2, 248), 16,                                          // %16 = OpLabel
      op(5, 133), 5, 10, 8, 8,                                 // %10 = OpFMul %5 %8 %8
      op(8, 12), 5, 11, 2, 50, 10, 8, 8,                       // %11 = OpExtInst %5 %2 Fma %10 %8 %8
      op(5, 148), 5, 12, 15, 15,                               // %12 = OpDot %5 %15 %15
      op(5, 128), 6, 13, 9, 9,                                 // %13 = OpIAdd %6 %9 %9
      op(6, 12), 5, 14, 2, 4, 11,                              // %14 = OpExtInst %5 %2 FAbs %11
      op(1, 253),                                              // OpReturn
      op(1, 56)};                                              // OpFunctionEnd
  ASSERT_EQ(validate(m, "vulkan1.2"), "");
  const Contraction before = scan_contraction(m);
  EXPECT_EQ(before.decorated, 1);
  EXPECT_EQ(before.undecorated, 3); // Fma, Dot, FAbs
  const std::vector<std::uint32_t> patched = with_no_contraction(m);
  const Contraction after = scan_contraction(patched);
  EXPECT_EQ(after.decorated, 4);
  EXPECT_EQ(after.undecorated, 0);
  EXPECT_EQ(after.duplicates, 0);
  EXPECT_EQ(after.fma_decorated, 1);
  EXPECT_EQ(patched.size(), m.size() + 9) << "the integer sum stays undecorated";
  EXPECT_EQ(validate(patched, "vulkan1.2"), "");
}

TEST(SpirvFloatControls, WordsThatAreNoModuleAreOneError) {
  EXPECT_THROW(with_no_contraction(std::vector<std::uint32_t>{1, 2, 3, 4, 5, 6}), Error);
  EXPECT_THROW(with_signed_zero_inf_nan_preserve(std::vector<std::uint32_t>{1, 2, 3, 4, 5, 6}), Error);
  // A first instruction claiming more words than there are: 0xffff words, in a module cut
  // to 1000 (the whole trace module is over 65,540 words, where 0xffff would still fit).
  std::vector<std::uint32_t> cut = words(trace_comp_spv);
  cut.resize(1000);
  cut[5] = 0xffff0011;
  EXPECT_THROW(with_signed_zero_inf_nan_preserve(cut), Error);
  EXPECT_THROW(with_no_contraction(cut), Error);
}

// Work-group sizes for the limits real devices report (subgroup size, maxComputeWorkGroupSize[0],
// maxComputeWorkGroupInvocations).
TEST(LocalSize, FitsTheSubgroupAndTheLimits) {
  auto fit = [](std::uint32_t sub, std::uint32_t x, std::uint32_t inv, std::uint32_t want) {
    return fit_local_size(ShaderLimits{sub, x, inv, false}, want);
  };
  EXPECT_EQ(fit(8, 1024, 1024, 64), 64u);   // lavapipe
  EXPECT_EQ(fit(32, 1024, 1024, 64), 64u);  // NVIDIA
  EXPECT_EQ(fit(64, 1024, 1024, 64), 64u);  // AMD (wave64)
  EXPECT_EQ(fit(32, 1024, 1024, 100), 128u); // rounded up to whole subgroups
  EXPECT_EQ(fit(32, 1024, 48, 64), 32u);    // invocation limit: down to whole subgroups
  EXPECT_EQ(fit(32, 16, 1024, 64), 16u);    // a limit below one subgroup: the limit
  EXPECT_EQ(fit(128, 1024, 1024, 64), 128u); // a subgroup wider than the wish
}

// This machine's device: the size the pipelines get fits it, and the kernels' pipelines
// (patched where the device supports the mode) are created and run by the backend tests
// under validation; here the limits are read and the patched module made.
TEST(LocalSize, ThisDevice) {
  std::shared_ptr<Context> ctx;
  try {
    ctx = Context::get("vulkan");
  } catch (const BackendUnavailable& e) {
    if (!test::missing_backends_allowed()) FAIL() << e.what();
    GTEST_SKIP() << e.what() << " (MASQ_ALLOW_MISSING_BACKENDS=1)";
  }
  const ShaderLimits l = shader_limits(*ctx);
  const std::uint32_t size = local_size(*ctx);
  EXPECT_GE(l.subgroup_size, 1u);
  EXPECT_LE(size, l.max_group_size_x);
  EXPECT_LE(size, l.max_group_invocations);
  if (std::getenv("MASQ_VK_LOCAL_SIZE") == nullptr) {
    EXPECT_EQ(size % l.subgroup_size, 0u);
  }
  const std::vector<std::uint32_t> d = device_spirv(*ctx, trace_comp_spv);
  EXPECT_EQ(scan(d).capabilities, l.preserve_float32 ? 1 : 0);
  std::printf("device: subgroup %u, work-group size %u, SignedZeroInfNanPreserve float32 %s\n", l.subgroup_size, size,
              l.preserve_float32 ? "yes" : "no");
}

} // namespace
