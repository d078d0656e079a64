// The kernel source compiled as C++, one translation unit per variant (each in its own
// namespace, see MASQ_KERNEL_VARIANT in kernels/shim.h).
#pragma once
#include "kernels/kernel_data.h"

namespace masq::cpu {
using TraceRangeFn = void (*)(const kernel::KernelData& kd, const kernel::Ray* rays, kernel::Hit* hits,
                              kernel::RayStats* stats, int begin, int end, int tlas_root);
void trace_range_plain(const kernel::KernelData& kd, const kernel::Ray* rays, kernel::Hit* hits,
                       kernel::RayStats* stats, int begin, int end, int tlas_root);
void trace_range_stats(const kernel::KernelData& kd, const kernel::Ray* rays, kernel::Hit* hits,
                       kernel::RayStats* stats, int begin, int end, int tlas_root);
} // namespace masq::cpu
