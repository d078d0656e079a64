// cpu bv kernel variant: obb nodes, counters off.
#define MASQ_KERNEL_VARIANT v_bv_obb_plain
#define MASQ_STATS 0
#define MASQ_BV_TYPE MASQ_BV_OBB
#define CPU_BV_FN trace_bv_obb_plain
#include "host/cpu/cpu_bv_kernel.inc"
