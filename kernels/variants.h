// The variant switches of kernels/variant_table.h in each language:
//  - GLSL: specialization constants (set by the Vulkan backends at pipeline creation),
//    so one SPIR-V module serves every variant and the driver's compiler removes the
//    dead branches;
//  - OpenCL C: macros, every row given by the host as a -D (host/opencl/cl_runtime.cpp);
//  - C++: variables of the kernel unit's namespace. In a generated cpu unit
//    (MASQ_CPU_UNIT defined, cmake/cpu_units.cmake) a row with cpu units >= 2 is the
//    constant MASQ_UNIT_<key> the unit was generated for, a row with 1 the constant
//    default, and a row with 0 a thread-local the unit's entry sets per dispatch.
//    Elsewhere (tests that include the kernels) every row is a thread-local starting at
//    its default, which the test may set.
#ifndef MASQ_KERNEL_VARIANTS_H
#define MASQ_KERNEL_VARIANTS_H
#include "shim.h"
#include "variant_table.h"

#if defined(MASQ_LANG_GLSL)
#define MASQ_GLSL_SPEC(NAME, key, T, DEF, ID, units, source) layout(constant_id = ID) const T NAME = DEF;
MASQ_VARIANTS(MASQ_GLSL_SPEC)
#elif defined(MASQ_LANG_CPP)
#if defined(MASQ_CPU_UNIT)
#define MASQ_CPU_SWITCH(NAME, key, T, DEF, ID, units, source) MASQ_CPU_SWITCH_##units(NAME, key, T, DEF)
#else
#define MASQ_CPU_SWITCH(NAME, key, T, DEF, ID, units, source) MASQ_CPU_SWITCH_0(NAME, key, T, DEF)
#endif
#define MASQ_CPU_SWITCH_0(NAME, key, T, DEF) inline thread_local T NAME = DEF;
#define MASQ_CPU_SWITCH_1(NAME, key, T, DEF) constexpr T NAME = DEF;
#define MASQ_CPU_SWITCH_UNITS(NAME, key, T, DEF) constexpr T NAME = MASQ_UNIT_##key;
#define MASQ_CPU_SWITCH_2 MASQ_CPU_SWITCH_UNITS
#define MASQ_CPU_SWITCH_3 MASQ_CPU_SWITCH_UNITS
#define MASQ_CPU_SWITCH_4 MASQ_CPU_SWITCH_UNITS
#define MASQ_CPU_SWITCH_5 MASQ_CPU_SWITCH_UNITS
#define MASQ_CPU_SWITCH_6 MASQ_CPU_SWITCH_UNITS
#define MASQ_CPU_SWITCH_7 MASQ_CPU_SWITCH_UNITS
#define MASQ_CPU_SWITCH_8 MASQ_CPU_SWITCH_UNITS
KERNEL_NS_BEGIN
MASQ_VARIANTS(MASQ_CPU_SWITCH)
KERNEL_NS_END
#endif

// The dimension of a traversal stack whose switch is NAME (MASQ_TLAS_STACK,
// MASQ_BLAS_STACK), in one of two forms (the MASQ_STACK_SIZED row; docs/kernels.md,
// "Stack forms"):
//  - fixed (MASQ_STACK_SIZED 0, the default): MASQ_STACK_MAX entries, a plain constant,
//    whatever the scene; nothing depends on how a driver sizes an array by a
//    specialization constant (the suspect of the H200's hang, docs/results.md);
//  - sized (1): NAME entries, so a GPU thread carries only what its scene's trees need.
//    GLSL takes the size from the specialization constant, in SPIR-V modules compiled
//    for this form (MASQ_STACK_SIZED_MODULE=1, a glslang -D: an array's dimension is not
//    a branch a specialization constant can choose); OpenCL C from the -D.
// C++ keeps the largest size either way (its switches need not be compile-time
// constants). The pushes are bounded by NAME itself on every backend and in both forms.
#if defined(MASQ_LANG_CPP)
#define MASQ_STACK_DIM(NAME) MASQ_STACK_MAX
#elif defined(MASQ_LANG_OPENCL)
#define MASQ_STACK_DIM(NAME) (MASQ_STACK_SIZED ? (NAME) : MASQ_STACK_MAX)
#elif defined(MASQ_STACK_SIZED_MODULE) && MASQ_STACK_SIZED_MODULE
#define MASQ_STACK_DIM(NAME) NAME
#else
#define MASQ_STACK_DIM(NAME) MASQ_STACK_MAX
#endif

#endif
