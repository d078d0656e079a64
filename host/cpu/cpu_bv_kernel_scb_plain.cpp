// cpu bv kernel variant: scb nodes, counters off.
#define MASQ_KERNEL_VARIANT v_bv_scb_plain
#define MASQ_STATS 0
#define MASQ_BV_TYPE MASQ_BV_SCB
#define CPU_BV_FN trace_bv_scb_plain
#include "host/cpu/cpu_bv_kernel.inc"
