// The kernel source compiled as C++, one translation unit per variant (each in its own
// namespace, see MASQ_KERNEL_VARIANT in kernels/shim.h): counters on/off x robust/fast.
// The phantom iteration limit is read at run time (kernel::curve_iters_runtime).
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
MASQ_CPU_DECLARE(trace_range_stats_robust)
MASQ_CPU_DECLARE(trace_range_stats_fast)
#undef MASQ_CPU_DECLARE
} // namespace masq::cpu
