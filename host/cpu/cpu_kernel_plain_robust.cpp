// cpu kernel variant: counters off, robust intersectors.
#define MASQ_KERNEL_VARIANT v_plain_robust
#define MASQ_STATS 0
#define MASQ_ROBUST 1
#define CPU_TRACE_FN trace_range_plain_robust
#include "host/cpu/cpu_kernel_variant.inc"
