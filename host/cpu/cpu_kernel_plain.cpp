// Counter-free variant of the kernels for the cpu backend.
#define MASQ_KERNEL_VARIANT v_plain
#define MASQ_STATS 0
#include "kernels/traverse.h"
#include "host/cpu/cpu_kernels.h"

namespace masq::cpu {
void trace_range_plain(const kernel::KernelData& kd, const kernel::Ray* rays, kernel::Hit* hits,
                       kernel::RayStats*, int begin, int end, int tlas_root) {
  for (int i = begin; i < end; ++i) hits[i] = kernel::v_plain::trace_closest(kd, rays[i], tlas_root).hit;
}
} // namespace masq::cpu
