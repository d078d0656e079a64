// How a scene and a trace call choose their kernel variant: the host sources of
// kernels/variant_table.h (FEATURES(...): the scene's KernelFeatures; TRACE(...): the
// call's TraceSwitches), each converted to the kernel's value by switch_value().
#pragma once
#include "bvh/packed_scene.h"
#include "host/kernel_variant.h"
#include "host/stack_size.h"
#include <cstdint>

namespace masq {

// What a trace call adds to the scene's features.
struct TraceSwitches {
  bool stats = false;   // per-ray counters wanted
  bool any_hit = false; // occlusion query: the first hit found ends the ray
};

// What the environment sets of every kernel variant, for A/B runs (docs/kernels.md):
//   MASQ_STEP_CHECK=on|off       the step budget and full-stack faults (default on)
//   MASQ_STACK_FORM=fixed|sized  traversal stacks of MASQ_STACK_MAX entries, or sized by
//                                the scene's need (default fixed; kernels/variants.h)
struct KernelKnobs {
  bool step_check = true;
  bool stack_sized = false;
};
// Read at every call; throws masq::Error naming the knob and its allowed values.
KernelKnobs kernel_knobs();

// The kernel's value of a host option.
inline std::int32_t switch_value(bool b) { return b ? 1 : 0; }
inline std::int32_t switch_value(int i) { return i; }
inline std::int32_t switch_value(Mode m) { return m == Mode::Robust ? 1 : 0; }
inline std::int32_t switch_value(CurveIsect c) { return c == CurveIsect::Roving ? MASQ_CURVE_ROVING : MASQ_CURVE_PHANTOM; }
inline std::int32_t switch_value(NodeFormat f) { return node_format_id(f); }
inline std::int32_t switch_value(const StackNeed& n) { return kernel_stack_size(n.entries, n.tree); }

KernelVariant kernel_variant(const KernelFeatures& features, const TraceSwitches& trace,
                             const KernelKnobs& knobs = kernel_knobs());

} // namespace masq
