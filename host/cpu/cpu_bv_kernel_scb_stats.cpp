// cpu bv kernel variant: scb nodes, counters on.
#define MASQ_KERNEL_VARIANT v_bv_scb_stats
#define MASQ_STATS 1
#define MASQ_BV_TYPE MASQ_BV_SCB
#define CPU_BV_FN trace_bv_scb_stats
#include "host/cpu/cpu_bv_kernel.inc"
