// Compile-time switches that make each dispatch carry only what its scene needs.
// C++ and OpenCL get them as preprocessor macros (-D); GLSL gets them as specialization
// constants (set by the Vulkan backend at pipeline creation), so one SPIR-V module
// serves every variant and the driver's compiler removes the dead branches.
#ifndef MASQ_KERNEL_VARIANTS_H
#define MASQ_KERNEL_VARIANTS_H
#include "shim.h"

#if defined(MASQ_LANG_GLSL)
layout(constant_id = 0) const bool MASQ_STATS = false;
layout(constant_id = 1) const bool MASQ_HAVE_TRIANGLES = true;
layout(constant_id = 2) const bool MASQ_HAVE_CAPSULES = true;
#else
#ifndef MASQ_STATS
#define MASQ_STATS 0
#endif
#ifndef MASQ_HAVE_TRIANGLES
#define MASQ_HAVE_TRIANGLES 1
#endif
#ifndef MASQ_HAVE_CAPSULES
#define MASQ_HAVE_CAPSULES 1
#endif
#endif

#define MASQ_STACK_SIZE 64

#endif
