#include "host/vulkan/spirv_float_controls.h"
#include "masq/error.h"
#include <cstring>
#include <set>
#include <string>

namespace masq::vk {

namespace {

// Opcodes and enumerants of the SPIR-V specification (unified1).
constexpr std::uint32_t kSpirvMagic = 0x07230203;
constexpr std::uint32_t kOpExtension = 10;
constexpr std::uint32_t kOpCapability = 17;
constexpr std::uint32_t kOpEntryPoint = 15;
constexpr std::uint32_t kOpExecutionMode = 16;
constexpr std::uint32_t kCapabilitySignedZeroInfNanPreserve = 4466;
constexpr std::uint32_t kModeSignedZeroInfNanPreserve = 4461;
constexpr std::uint32_t kVersionWithFloatControls = 0x00010400; // SPIR-V 1.4
constexpr std::size_t kHeaderWords = 5;
constexpr std::uint32_t kOpExtInstImport = 11;
constexpr std::uint32_t kOpExtInst = 12;
constexpr std::uint32_t kOpTypeFloat = 22;
constexpr std::uint32_t kOpTypeVector = 23;
constexpr std::uint32_t kOpTypeMatrix = 24;
constexpr std::uint32_t kOpDecorate = 71;
constexpr std::uint32_t kDecorationNoContraction = 42;

std::uint32_t instruction(std::uint32_t words, std::uint32_t opcode) { return words << 16 | opcode; }

// OpExtension "SPV_KHR_float_controls": the string's bytes, nul-terminated, padded to words.
std::vector<std::uint32_t> extension_instruction() {
  const char name[] = "SPV_KHR_float_controls";
  std::vector<std::uint32_t> words((sizeof(name) + 3) / 4, 0);
  std::memcpy(words.data(), name, sizeof(name));
  words.insert(words.begin(), instruction(std::uint32_t(words.size() + 1), kOpExtension));
  return words;
}

// Throws unless `spirv` starts with a SPIR-V header.
void check_header(std::span<const std::uint32_t> spirv) {
  if (spirv.size() < kHeaderWords || spirv[0] != kSpirvMagic)
    throw Error("spirv: not a SPIR-V module (" + std::to_string(spirv.size()) + " words, no magic number)");
}

// The words of the instruction at `at`; throws if it runs past the end.
std::uint32_t instruction_words(std::span<const std::uint32_t> spirv, std::size_t at) {
  const std::uint32_t words = spirv[at] >> 16;
  if (words == 0 || at + words > spirv.size()) throw Error("spirv: truncated instruction at word " + std::to_string(at));
  return words;
}

// Arithmetic on float operands only (the SPIR-V specification's "Arithmetic
// Instructions" whose operands are floating point): every one may be fused with its
// neighbours or re-associated by a driver unless its result is decorated.
bool is_float_arithmetic(std::uint32_t opcode) {
  switch (opcode) {
    case 127: // OpFNegate
    case 129: // OpFAdd
    case 131: // OpFSub
    case 133: // OpFMul
    case 136: // OpFDiv
    case 140: // OpFRem
    case 141: // OpFMod
    case 142: // OpVectorTimesScalar
    case 143: // OpMatrixTimesScalar
    case 144: // OpVectorTimesMatrix
    case 145: // OpMatrixTimesVector
    case 146: // OpMatrixTimesMatrix
    case 147: // OpOuterProduct
    case 148: // OpDot
      return true;
    default:
      return false;
  }
}

// The debug and annotation instructions that precede the module's types: the new
// decorations go after the last of them, which keeps the layout's order.
bool is_preamble(std::uint32_t opcode) {
  switch (opcode) {
    case 2: case 3: case 4: case 5: case 6: case 7: // OpSource*, OpName, OpMemberName, OpString
    case kOpExtension: case kOpExtInstImport: case 14: case kOpEntryPoint: case kOpExecutionMode: case kOpCapability:
    case kOpDecorate: case 72: case 73: case 74: case 75: // OpMemberDecorate, decoration groups
    case 330: case 331: case 332: case 5632: case 5633: // OpModuleProcessed, OpExecutionModeId, OpDecorateId/String
      return true;
    default:
      return false;
  }
}

} // namespace

std::vector<std::uint32_t> with_no_contraction(std::span<const std::uint32_t> spirv) {
  check_header(spirv);
  std::uint32_t glsl_set = 0; // 0: the module imports no GLSL.std.450
  std::set<std::uint32_t> float_types, decorated;
  std::vector<std::uint32_t> targets;
  std::size_t end_of_preamble = 0;
  for (std::size_t at = kHeaderWords; at < spirv.size();) {
    const std::uint32_t words = instruction_words(spirv, at), opcode = spirv[at] & 0xffff;
    if (end_of_preamble == 0 && !is_preamble(opcode)) end_of_preamble = at;
    if (opcode == kOpExtInstImport && words >= 3 &&
        std::strncmp(reinterpret_cast<const char*>(&spirv[at + 2]), "GLSL.std.450", (words - 2) * 4) == 0)
      glsl_set = spirv[at + 1];
    if (opcode == kOpDecorate && words >= 3 && spirv[at + 2] == kDecorationNoContraction) decorated.insert(spirv[at + 1]);
    if (opcode == kOpTypeFloat && words >= 2) float_types.insert(spirv[at + 1]);
    if ((opcode == kOpTypeVector || opcode == kOpTypeMatrix) && words >= 3 && float_types.count(spirv[at + 2]))
      float_types.insert(spirv[at + 1]);
    const bool arithmetic = is_float_arithmetic(opcode) && words >= 3;
    const bool glsl_float = opcode == kOpExtInst && words >= 5 && glsl_set != 0 && spirv[at + 3] == glsl_set &&
                            float_types.count(spirv[at + 1]);
    if ((arithmetic || glsl_float) && !decorated.count(spirv[at + 2])) {
      targets.push_back(spirv[at + 2]);
      decorated.insert(spirv[at + 2]);
    }
    at += words;
  }
  if (end_of_preamble == 0) end_of_preamble = spirv.size();
  std::vector<std::uint32_t> out;
  out.reserve(spirv.size() + 3 * targets.size());
  out.insert(out.end(), spirv.begin(), spirv.begin() + std::ptrdiff_t(end_of_preamble));
  for (std::uint32_t id : targets) out.insert(out.end(), {instruction(3, kOpDecorate), id, kDecorationNoContraction});
  out.insert(out.end(), spirv.begin() + std::ptrdiff_t(end_of_preamble), spirv.end());
  return out;
}

std::vector<std::uint32_t> with_signed_zero_inf_nan_preserve(std::span<const std::uint32_t> spirv) {
  check_header(spirv);
  // The layout's order (capabilities, extensions, ..., entry points, execution modes)
  // says where each addition goes: after the last of its kind, or of the kind before it.
  std::size_t after_capabilities = kHeaderWords, after_extensions = 0, after_entries = 0, after_modes = 0;
  std::vector<std::uint32_t> entries;
  for (std::size_t at = kHeaderWords; at < spirv.size();) {
    const std::uint32_t words = instruction_words(spirv, at), opcode = spirv[at] & 0xffff;
    if (opcode == kOpCapability && words >= 2 && spirv[at + 1] == kCapabilitySignedZeroInfNanPreserve)
      return {spirv.begin(), spirv.end()};
    if (opcode == kOpCapability) after_capabilities = at + words;
    if (opcode == kOpExtension) after_extensions = at + words;
    if (opcode == kOpEntryPoint && words >= 3) {
      entries.push_back(spirv[at + 2]);
      after_entries = at + words;
    }
    if (opcode == kOpExecutionMode) after_modes = at + words;
    at += words;
  }
  if (entries.empty()) throw Error("spirv: the module has no entry point");
  if (after_extensions == 0) after_extensions = after_capabilities;
  if (after_modes == 0) after_modes = after_entries;

  std::vector<std::uint32_t> modes;
  for (std::uint32_t entry : entries)
    modes.insert(modes.end(), {instruction(4, kOpExecutionMode), entry, kModeSignedZeroInfNanPreserve, 32});
  const std::vector<std::uint32_t> capability{instruction(2, kOpCapability), kCapabilitySignedZeroInfNanPreserve};
  const bool needs_extension = spirv[1] < kVersionWithFloatControls;

  std::vector<std::uint32_t> out;
  out.reserve(spirv.size() + 32);
  auto copy = [&](std::size_t from, std::size_t to) { out.insert(out.end(), spirv.begin() + from, spirv.begin() + to); };
  copy(0, after_capabilities);
  out.insert(out.end(), capability.begin(), capability.end());
  copy(after_capabilities, after_extensions);
  if (needs_extension) {
    const std::vector<std::uint32_t> ext = extension_instruction();
    out.insert(out.end(), ext.begin(), ext.end());
  }
  copy(after_extensions, after_modes);
  out.insert(out.end(), modes.begin(), modes.end());
  copy(after_modes, spirv.size());
  return out;
}

} // namespace masq::vk
