// cpu kernel variant: counters on, fast intersectors.
#define MASQ_KERNEL_VARIANT v_stats_fast
#define MASQ_STATS 1
#define MASQ_ROBUST 0
#define CPU_TRACE_FN trace_range_stats_fast
#include "host/cpu/cpu_kernel_variant.inc"
