// The entry every generated cpu kernel unit defines (cmake/cpu_units.cmake). A light
// header: each unit includes it beside the kernel source.
#pragma once
#include "host/kernel_variant.h"
#include "kernels/kernel_data.h"

namespace masq::cpu {

// Traces rays [begin, end) of a batch with the switches the unit reads at run time taken
// from v. root: the TLAS root (trace units) or the node count (bv units); budget: the
// step budget of one tree walk (kernel::TraceParams::step_budget).
using UnitFn = void (*)(const kernel::KernelData& kd, const KernelVariant& v, const kernel::Ray* rays,
                        kernel::Hit* hits, kernel::RayStats* stats, int begin, int end, int root, int budget);
#define MASQ_CPU_UNIT_DECLARE(name)                                                                   \
  void name(const kernel::KernelData& kd, const KernelVariant& v, const kernel::Ray* rays, kernel::Hit* hits, \
            kernel::RayStats* stats, int begin, int end, int root, int budget);

} // namespace masq::cpu
