// SignedZeroInfNanPreserve for the kernels' SPIR-V. The kernels rely on IEEE infinities
// and NaN (infinite entry distances mean "missed", NaN comparisons fail), and a Vulkan
// driver may otherwise assume neither occurs. GLSL cannot request the execution mode,
// so it is added to the compiled module's words at pipeline creation, where the device
// supports it (docs/robustness.md, "Float semantics").
#pragma once
#include <cstdint>
#include <span>
#include <vector>

namespace masq::vk {

// `spirv` with OpCapability SignedZeroInfNanPreserve, OpExecutionMode <entry>
// SignedZeroInfNanPreserve 32 for every entry point, and OpExtension
// "SPV_KHR_float_controls" when the module's version is below 1.4 (where the mode is not
// core). A module that already declares the capability is returned unchanged. Throws
// masq::Error for words that are no SPIR-V module (bad magic, truncated instruction).
std::vector<std::uint32_t> with_signed_zero_inf_nan_preserve(std::span<const std::uint32_t> spirv);

} // namespace masq::vk
