// Counting variant of the kernels for the cpu backend.
#define MASQ_KERNEL_VARIANT v_stats
#define MASQ_STATS 1
#include "kernels/traverse.h"
#include "host/cpu/cpu_kernels.h"

namespace masq::cpu {
void trace_range_stats(const kernel::KernelData& kd, const kernel::Ray* rays, kernel::Hit* hits,
                       kernel::RayStats* stats, int begin, int end, int tlas_root) {
  for (int i = begin; i < end; ++i) {
    kernel::v_stats::TraceOut o = kernel::v_stats::trace_closest(kd, rays[i], tlas_root);
    hits[i] = o.hit;
    stats[i] = o.stats;
  }
}
} // namespace masq::cpu
