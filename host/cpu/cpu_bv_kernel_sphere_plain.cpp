// cpu bv kernel variant: sphere nodes, counters off.
#define MASQ_KERNEL_VARIANT v_bv_sphere_plain
#define MASQ_STATS 0
#define MASQ_BV_TYPE MASQ_BV_SPHERE
#define CPU_BV_FN trace_bv_sphere_plain
#include "host/cpu/cpu_bv_kernel.inc"
