// cpu kernel variant: counters off, robust intersectors, node format q8 fixed at compile
// time (the timed variants; the counter variants read the format at run time).
#define MASQ_KERNEL_VARIANT v_plain_robust_q8
#define MASQ_STATS 0
#define MASQ_ROBUST 1
#define MASQ_NODE_FORMAT MASQ_NODES_Q8
#define CPU_TRACE_FN trace_range_plain_robust_q8
#include "host/cpu/cpu_kernel_variant.inc"
