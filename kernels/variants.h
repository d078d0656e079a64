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
// id 3: work-group size (local_size_x_id in the entry points)
layout(constant_id = 4) const bool MASQ_HAVE_CONES = true;
layout(constant_id = 5) const bool MASQ_HAVE_SPHERES = true;
layout(constant_id = 6) const bool MASQ_HAVE_CURVES = true;
layout(constant_id = 7) const bool MASQ_ROBUST = true;
layout(constant_id = 8) const int MASQ_CURVE_ITERS = 24;
layout(constant_id = 9) const bool MASQ_ANY_HIT = false;
layout(constant_id = 10) const bool MASQ_SINGLE_BLAS = false;
layout(constant_id = 11) const int MASQ_NODE_FORMAT = 0;
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
#ifndef MASQ_HAVE_CONES
#define MASQ_HAVE_CONES 1
#endif
#ifndef MASQ_HAVE_SPHERES
#define MASQ_HAVE_SPHERES 1
#endif
#ifndef MASQ_HAVE_CURVES
#define MASQ_HAVE_CURVES 1
#endif
// Robust intersectors and the padded (conservative) masquerade box test; 0 selects
// the fast intersectors and the unpadded box test (benchmarked against each other).
#ifndef MASQ_ROBUST
#define MASQ_ROBUST 1
#endif
// Phantom curve iteration limit. The cpu backend reads it at run time (one compiled
// variant serves every limit); OpenCL gets it as -D.
#ifndef MASQ_CURVE_ITERS
#if defined(MASQ_LANG_CPP)
namespace masq::kernel {
inline thread_local int curve_iters_runtime = 24;
}
#define MASQ_CURVE_ITERS (::masq::kernel::curve_iters_runtime)
#else
#define MASQ_CURVE_ITERS 24
#endif
#endif
// Occlusion queries (shadow rays): stop at the first hit found, not the closest. The cpu
// backend reads it at run time like the iteration limit (a branch on a per-dispatch
// constant costs nothing measurable there); OpenCL gets it as -D.
#ifndef MASQ_ANY_HIT
#if defined(MASQ_LANG_CPP)
namespace masq::kernel {
inline thread_local bool any_hit_runtime = false;
}
#define MASQ_ANY_HIT (::masq::kernel::any_hit_runtime)
#else
#define MASQ_ANY_HIT 0
#endif
#endif
// The scene is one BLAS under one identity instance (a mesh, a hair file in ref): no
// TLAS stage and no ray transform; the BLAS of instance 0 is traversed with the world
// ray. Run time on cpu, -D on OpenCL.
#ifndef MASQ_SINGLE_BLAS
#if defined(MASQ_LANG_CPP)
namespace masq::kernel {
inline thread_local bool single_blas_runtime = false;
}
#define MASQ_SINGLE_BLAS (::masq::kernel::single_blas_runtime)
#else
#define MASQ_SINGLE_BLAS 0
#endif
#endif
// The scene's BVH node format (MASQ_NODES_* in kernels/layout.h): each variant carries
// only its own node test. Run time on cpu (one branch per node visit), -D on OpenCL.
#ifndef MASQ_NODE_FORMAT
#if defined(MASQ_LANG_CPP)
namespace masq::kernel {
inline thread_local int node_format_runtime = 0;
}
#define MASQ_NODE_FORMAT (::masq::kernel::node_format_runtime)
#else
#define MASQ_NODE_FORMAT 0
#endif
#endif
#endif

#define MASQ_STACK_SIZE 64

#endif
