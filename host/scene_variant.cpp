#include "host/scene_variant.h"
#include "masq/error.h"
#include <cstdlib>
#include <string>

namespace masq {

namespace {
// The value of an on/off knob (unset or empty: `fallback`).
bool knob_choice(const char* name, const char* on, const char* off, bool fallback) {
  const char* v = std::getenv(name);
  if (v == nullptr || *v == '\0') return fallback;
  if (std::string(v) == on) return true;
  if (std::string(v) == off) return false;
  throw Error(std::string(name) + "='" + v + "' is not '" + on + "' or '" + off + "'");
}
} // namespace

KernelKnobs kernel_knobs() {
  KernelKnobs k;
  k.step_check = knob_choice("MASQ_STEP_CHECK", "on", "off", true);
  k.stack_sized = knob_choice("MASQ_STACK_FORM", "sized", "fixed", false);
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
