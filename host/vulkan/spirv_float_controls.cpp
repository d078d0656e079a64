#include "host/vulkan/spirv_float_controls.h"
#include "masq/error.h"
#include <cstring>
#include <string>

namespace masq::vk {

namespace {

// Opcodes and enumerants of the SPIR-V specification (unified1).
constexpr std::uint32_t kMagic = 0x07230203;
constexpr std::uint32_t kOpExtension = 10;
constexpr std::uint32_t kOpCapability = 17;
constexpr std::uint32_t kOpEntryPoint = 15;
constexpr std::uint32_t kOpExecutionMode = 16;
constexpr std::uint32_t kCapabilitySignedZeroInfNanPreserve = 4466;
constexpr std::uint32_t kModeSignedZeroInfNanPreserve = 4461;
constexpr std::uint32_t kVersionWithFloatControls = 0x00010400; // SPIR-V 1.4
constexpr std::size_t kHeaderWords = 5;

std::uint32_t instruction(std::uint32_t words, std::uint32_t opcode) { return words << 16 | opcode; }

// OpExtension "SPV_KHR_float_controls": the string's bytes, nul-terminated, padded to words.
std::vector<std::uint32_t> extension_instruction() {
  const char name[] = "SPV_KHR_float_controls";
  std::vector<std::uint32_t> words((sizeof(name) + 3) / 4, 0);
  std::memcpy(words.data(), name, sizeof(name));
  words.insert(words.begin(), instruction(std::uint32_t(words.size() + 1), kOpExtension));
  return words;
}

} // namespace

std::vector<std::uint32_t> with_signed_zero_inf_nan_preserve(std::span<const std::uint32_t> spirv) {
  if (spirv.size() < kHeaderWords || spirv[0] != kMagic)
    throw Error("spirv: not a SPIR-V module (" + std::to_string(spirv.size()) + " words, no magic number)");
  // The layout's order (capabilities, extensions, ..., entry points, execution modes)
  // says where each addition goes: after the last of its kind, or of the kind before it.
  std::size_t after_capabilities = kHeaderWords, after_extensions = 0, after_entries = 0, after_modes = 0;
  std::vector<std::uint32_t> entries;
  for (std::size_t at = kHeaderWords; at < spirv.size();) {
    const std::uint32_t words = spirv[at] >> 16, opcode = spirv[at] & 0xffff;
    if (words == 0 || at + words > spirv.size())
      throw Error("spirv: truncated instruction at word " + std::to_string(at));
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
