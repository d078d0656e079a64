#include "host/scene_variant.h"

namespace masq {

KernelVariant kernel_variant(const KernelFeatures& features, const TraceSwitches& trace) {
  KernelVariant v;
#define MASQ_FROM_FEATURES(member) features.member
#define MASQ_FROM_TRACE(member) trace.member
#define MASQ_VARIANT_SET(NAME, key, T, DEF, ID, units, source) v.key = switch_value(MASQ_FROM_##source);
  MASQ_VARIANTS(MASQ_VARIANT_SET)
#undef MASQ_VARIANT_SET
#undef MASQ_FROM_TRACE
#undef MASQ_FROM_FEATURES
  return v;
}

} // namespace masq
