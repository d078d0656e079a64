// cpu kernel variant: counters on, robust intersectors.
#define MASQ_KERNEL_VARIANT v_stats_robust
#define MASQ_STATS 1
#define MASQ_ROBUST 1
#define CPU_TRACE_FN trace_range_stats_robust
#include "host/cpu/cpu_kernel_variant.inc"
