// cpu kernel variant: counters off, fast intersectors.
#define MASQ_KERNEL_VARIANT v_plain_fast
#define MASQ_STATS 0
#define MASQ_ROBUST 0
#define CPU_TRACE_FN trace_range_plain_fast
#include "host/cpu/cpu_kernel_variant.inc"
