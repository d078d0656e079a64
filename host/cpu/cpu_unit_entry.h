// What a generated cpu kernel unit's entry needs besides its kernel: its signature and
// the setting of the switches the cpu reads at run time ("cpu units" 0 in
// kernels/variant_table.h) from the dispatch's KernelVariant, once per call.
#pragma once
#include "host/cpu/cpu_unit_fn.h"

#define MASQ_CPU_SET_SWITCH(NAME, key, T, DEF, ID, units, source) MASQ_CPU_SET_SWITCH_##units(NAME, key, T)
#define MASQ_CPU_SET_SWITCH_0(NAME, key, T) ns::NAME = static_cast<T>(variant.key);
#define MASQ_CPU_SET_SWITCH_1(NAME, key, T)
#define MASQ_CPU_SET_SWITCH_2(NAME, key, T)
#define MASQ_CPU_SET_SWITCH_3(NAME, key, T)
#define MASQ_CPU_SET_SWITCH_4(NAME, key, T)
#define MASQ_CPU_SET_SWITCH_5(NAME, key, T)
#define MASQ_CPU_SET_SWITCH_6(NAME, key, T)
#define MASQ_CPU_SET_SWITCH_7(NAME, key, T)
#define MASQ_CPU_SET_SWITCH_8(NAME, key, T)
// ns: the unit's kernel namespace; variant: the dispatch's KernelVariant.
#define MASQ_CPU_SET_RUNTIME_SWITCHES(ns_, variant_) \
  {                                                  \
    namespace ns = ns_;                              \
    const KernelVariant& variant = variant_;         \
    MASQ_VARIANTS(MASQ_CPU_SET_SWITCH)               \
  }
