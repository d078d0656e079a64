// cpu bv kernel variant: aabb nodes, counters on.
#define MASQ_KERNEL_VARIANT v_bv_aabb_stats
#define MASQ_STATS 1
#define MASQ_BV_TYPE MASQ_BV_AABB
#define CPU_BV_FN trace_bv_aabb_stats
#include "host/cpu/cpu_bv_kernel.inc"
