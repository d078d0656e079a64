#include "host/scene_variant.h"
#include "host/limit_knob.h"

namespace masq {

KernelKnobs kernel_knobs() {
  KernelKnobs k;
  k.step_check = choice_knob("", Knob::StepCheck, "on");
  k.stack_sized = choice_knob("", Knob::StackForm, "sized");
  return k;
}

KernelVariant kernel_variant(const KernelFeatures& features, const TraceSwitches& trace, const KernelKnobs& knobs) {
  KernelVariant v;
#define MASQ_FROM_FEATURES(member) features.member
#define MASQ_FROM_TRACE(member) trace.member
#define MASQ_FROM_KNOBS(member) knobs.member
#define MASQ_VARIANT_SET(NAME, key, T, DEF, ID, units, source) v.key = switch_value(MASQ_FROM_##source);
  MASQ_VARIANTS(MASQ_VARIANT_SET)
#undef MASQ_VARIANT_SET
#undef MASQ_FROM_KNOBS
#undef MASQ_FROM_TRACE
#undef MASQ_FROM_FEATURES
  return v;
}

} // namespace masq
