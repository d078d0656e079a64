// The kernel source compiled as C++, one translation unit per variant (each in its own
// namespace, see MASQ_KERNEL_VARIANT in kernels/shim.h): counters on/off x robust/fast,
// and for the counter-free (timed) variants also per node format: a run-time format
// switch cost the cpu w4 traversal 5-8% (the 8-slot loops could not be unrolled). The
// counter variants, the phantom iteration limit, any-hit and single-BLAS are read at run
// time (kernels/variants.h).
#pragma once
#include "kernels/kernel_data.h"

namespace masq::cpu {
using TraceRangeFn = void (*)(const kernel::KernelData& kd, const kernel::Ray* rays, kernel::Hit* hits,
                              kernel::RayStats* stats, int begin, int end, int tlas_root);
#define MASQ_CPU_DECLARE(name)                                                                                  \
  void name(const kernel::KernelData& kd, const kernel::Ray* rays, kernel::Hit* hits, kernel::RayStats* stats, \
            int begin, int end, int tlas_root);
MASQ_CPU_DECLARE(trace_range_plain_robust)
MASQ_CPU_DECLARE(trace_range_plain_fast)
MASQ_CPU_DECLARE(trace_range_plain_robust_w8)
MASQ_CPU_DECLARE(trace_range_plain_fast_w8)
MASQ_CPU_DECLARE(trace_range_plain_robust_q8)
MASQ_CPU_DECLARE(trace_range_plain_fast_q8)
MASQ_CPU_DECLARE(trace_range_stats_robust)
MASQ_CPU_DECLARE(trace_range_stats_fast)
#undef MASQ_CPU_DECLARE
} // namespace masq::cpu
