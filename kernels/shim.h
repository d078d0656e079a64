// Language shim: lets the kernel sources under kernels/ compile as GLSL 4.60 (Vulkan),
// OpenCL C 1.2 (PoCL or any OpenCL device) and C++20 (the cpu backend).
// Rules of the dialect (see docs/kernels.md): pure functions returning structs, no
// pointers/references/overloads/templates/recursion, fixed-size arrays, swizzles only
// .x/.y/.z, GPU-visible structs made of 4-byte scalars only.
#ifndef MASQ_KERNEL_SHIM_H
#define MASQ_KERNEL_SHIM_H

#if defined(__cplusplus)
// ---------------------------------------------------------------- C++ (cpu backend)
#include <glm/glm.hpp>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#define MASQ_LANG_CPP 1
#define FN inline
// A function the C++ build inlines into every caller. GCC's own choice kept
// traverse_blas out of line, and its call then spilled the ray and the nearest hit to
// the stack as parts and read them back whole, a store-forwarding stall per call: inlined,
// the bear's ref rays traced 1.21x (primary) and 1.11x (shadow) as fast on cpu.
#define FN_INLINED inline __attribute__((always_inline))
#define STRUCT_BEGIN(N) struct N {
#define STRUCT_END(N) };
#define VEC3(x, y, z) vec3((x), (y), (z))
#define STATIC_ASSERT(cond, name) static_assert(cond, #name)
// Layout structs live in masq::kernel; functions in a per-variant inner namespace, so
// the cpu backend can compile several variants (stats on/off, ...) into one binary.
#ifndef MASQ_KERNEL_VARIANT
#define MASQ_KERNEL_VARIANT v_default
#endif
#define LAYOUT_NS_BEGIN namespace masq::kernel {
#define LAYOUT_NS_END }
#define KERNEL_NS_BEGIN namespace masq::kernel { namespace MASQ_KERNEL_VARIANT {
#define KERNEL_NS_END } }
namespace masq::kernel {
using vec3 = glm::vec3;
using uint = std::uint32_t;
// Only the glm names are brought in, so calls never become ambiguous with std::.
using glm::cross;
using glm::dot;
using glm::length;
using glm::max;
using glm::min;
using glm::normalize;
using glm::sqrt;
inline float fabs_(float x) { return std::fabs(x); }
inline vec3 vabs_(vec3 v) { return glm::abs(v); }
inline float inf_() { return std::numeric_limits<float>::infinity(); }
// Bit and value conversions of 32-bit words (node formats read raw words).
inline float as_float_(uint u) { return std::bit_cast<float>(u); }
inline uint f2u_(float x) { return std::bit_cast<uint>(x); }
inline int u2i_(uint u) { return std::bit_cast<int>(u); }
inline float u2f_(uint u) { return float(u); }
inline float i2f_(int i) { return float(i); }
} // namespace masq::kernel

#elif defined(__OPENCL_VERSION__)
// ---------------------------------------------------------------- OpenCL C 1.2
// OpenCL C lets the compiler fuse a*b + c within an expression (FP_CONTRACT defaults to
// ON; PoCL does fuse on FMA hardware): off for the rest of the program, before any of
// its code (every kernel header includes this one first; see "Contraction" below).
#pragma OPENCL FP_CONTRACT OFF
#define MASQ_LANG_OPENCL 1
#define FN inline
#define FN_INLINED inline
#define STRUCT_BEGIN(N) typedef struct N {
#define STRUCT_END(N) } N;
#define VEC3(x, y, z) ((float3)((x), (y), (z)))
// C99 has no static_assert: a negative array size fails the build.
#define STATIC_ASSERT(cond, name) typedef char static_assert_##name[(cond) ? 1 : -1]
#define KERNEL_NS_BEGIN
#define KERNEL_NS_END
#define LAYOUT_NS_BEGIN
#define LAYOUT_NS_END
typedef float3 vec3;
#define fabs_(x) fabs(x)
#define vabs_(v) fabs(v)
#define inf_() INFINITY
#define as_float_(u) as_float(u)
#define f2u_(x) as_uint(x)
#define u2i_(u) as_int(u)
#define u2f_(u) convert_float(u)
#define i2f_(i) convert_float(i)

#else
// ---------------------------------------------------------------- GLSL 4.60 (Vulkan)
#define MASQ_LANG_GLSL 1
#define FN
#define FN_INLINED
#define STRUCT_BEGIN(N) struct N {
#define STRUCT_END(N) };
#define VEC3(x, y, z) vec3((x), (y), (z))
#define STATIC_ASSERT(cond, name)
#define KERNEL_NS_BEGIN
#define KERNEL_NS_END
#define LAYOUT_NS_BEGIN
#define LAYOUT_NS_END
#define fabs_(x) abs(x)
#define vabs_(v) abs(v)
#define inf_() uintBitsToFloat(0x7f800000u)
#define as_float_(u) uintBitsToFloat(u)
#define f2u_(x) floatBitsToUint(x)
#define u2i_(u) int(u)
#define u2f_(u) float(u)
#define i2f_(i) float(i)
#endif

// Contraction: none, on every backend (docs/robustness.md, "Float semantics"). Every
// a*b + c rounds twice as written: C++ is compiled with -ffp-contract=off, OpenCL C gets
// `#pragma OPENCL FP_CONTRACT OFF` (above, before any kernel code), and the Vulkan
// backends decorate every float operation of the SPIR-V NoContraction at pipeline
// creation (host/vulkan/spirv_float_controls.h). That pass covers every expression, so
// the kernels carry no GLSL `precise` (a MASQ_PRECISE macro marked a few expressions
// before the pass existed: redundant now, and the rest of a function could still fuse).
//
// two_prod_err_(a, b, p), p = a * b rounded: the product's rounding error a*b - p,
// exactly (an error-free transform, for the curve's accurate dot products; exact unless
// a*b overflows or falls below ~2^-100). C++ and OpenCL C: one explicit fused
// multiply-add. GLSL: fma() is only a fused operation where the driver keeps it one, and
// lavapipe lowers every 32-bit ffma into a product and a sum (even one decorated
// NoContraction: measured), so GLSL takes Dekker's product of Veltkamp's halves instead
// (split constant 2^12 + 1), exact in round-to-nearest fp32 as long as nothing is
// contracted or reassociated, which the NoContraction pass guarantees. Exact both ways,
// so every backend gets the same bits.
#if defined(MASQ_LANG_CPP)
namespace masq::kernel {
inline float two_prod_err_(float a, float b, float p) { return std::fma(a, b, -p); }
} // namespace masq::kernel
#elif defined(MASQ_LANG_OPENCL)
#define two_prod_err_(a, b, p) fma((a), (b), -(p))
#else
float two_prod_err_(float a, float b, float p) {
  float ca = 4097.0f * a;
  float ah = ca - (ca - a);
  float al = a - ah;
  float cb = 4097.0f * b;
  float bh = cb - (cb - b);
  float bl = b - bh;
  return ((ah * bh - p) + ah * bl + al * bh) + al * bl;
}
#endif

// Buffer access. GLSL binds each array as a global SSBO (or reads it by device address); OpenCL and C++ pass one struct
// of pointers (KernelData) through every function that reads scene data, the way
// Blender Cycles declares its kernel arrays once for every backend.
#if defined(MASQ_LANG_GLSL)
#define KD_PARAM
#define KD_ARG
// KD(name) is defined with the arrays in kernel_data.h (bound or addressed).
#elif defined(MASQ_LANG_OPENCL)
#define KD_PARAM const KernelData kd,
#define KD_ARG kd,
#define KD(name) kd.name
#else
// C++: by reference. By value, every call the compiler does not inline (traverse_blas,
// once per instance a ray enters) copied the struct's 160 bytes onto the stack.
#define KD_PARAM const KernelData& kd,
#define KD_ARG kd,
#define KD(name) kd.name
#endif

#endif
