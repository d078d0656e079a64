// The float semantics the kernels rely on, added to their compiled SPIR-V at pipeline
// creation because GLSL cannot state them (docs/robustness.md, "Float semantics"):
// - SignedZeroInfNanPreserve: the kernels rely on IEEE infinities and NaN (infinite
//   entry distances mean "missed", NaN comparisons fail), and a Vulkan driver may
//   otherwise assume neither occurs. Added where the device supports it.
// - NoContraction on every floating-point arithmetic result: each operation rounds
//   exactly as written, as on the cpu (-ffp-contract=off) and in OpenCL (FP_CONTRACT
//   OFF), so the backends return the same bits; and fma() stays one fused operation
//   (without the decoration a driver may split GLSL.std.450 Fma into a product and a
//   sum, which breaks the curve's error-free products). Added on every device: the
//   decoration is core SPIR-V.
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

// `spirv` with OpDecorate <id> NoContraction for the result of every floating-point
// arithmetic instruction (OpFNegate, OpFAdd, OpFSub, OpFMul, OpFDiv, OpFRem, OpFMod,
// OpVectorTimesScalar, OpMatrixTimesScalar, OpVectorTimesMatrix, OpMatrixTimesVector,
// OpMatrixTimesMatrix, OpOuterProduct, OpDot) and of every GLSL.std.450 instruction
// whose result is a float scalar, vector or matrix (Fma, Length, Normalize, Cross, ...:
// drivers expand those into products and sums too), except ids that carry it already
// (glslang's `precise`). Patching twice adds nothing. Throws masq::Error as above.
std::vector<std::uint32_t> with_no_contraction(std::span<const std::uint32_t> spirv);

} // namespace masq::vk
