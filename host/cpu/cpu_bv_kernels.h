// The bv kernels compiled as C++: one translation unit per (BV type, counters on/off),
// each in its own namespace (MASQ_KERNEL_VARIANT). Robust intersectors only.
#pragma once
#include "kernels/kernel_data.h"

namespace masq::cpu {
using BvRangeFn = void (*)(const kernel::KernelData& kd, const kernel::Ray* rays, kernel::Hit* hits,
                           kernel::RayStats* stats, int begin, int end, int node_count);
#define MASQ_CPU_BV_DECLARE(name)                                                                               \
  void name(const kernel::KernelData& kd, const kernel::Ray* rays, kernel::Hit* hits, kernel::RayStats* stats, \
            int begin, int end, int node_count);
MASQ_CPU_BV_DECLARE(trace_bv_aabb_plain)
MASQ_CPU_BV_DECLARE(trace_bv_aabb_stats)
MASQ_CPU_BV_DECLARE(trace_bv_sphere_plain)
MASQ_CPU_BV_DECLARE(trace_bv_sphere_stats)
MASQ_CPU_BV_DECLARE(trace_bv_obb_plain)
MASQ_CPU_BV_DECLARE(trace_bv_obb_stats)
MASQ_CPU_BV_DECLARE(trace_bv_scb_plain)
MASQ_CPU_BV_DECLARE(trace_bv_scb_stats)
#undef MASQ_CPU_BV_DECLARE
} // namespace masq::cpu
