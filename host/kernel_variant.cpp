#include "host/kernel_variant.h"
#include "kernels/layout.h"
#include "masq/error.h"
#include <string>

namespace masq {

namespace {

// The table's rules that the compiler can check: unique specialization ids, clear of
// the work-group size's; the cpu's node-format units cover every node format.
constexpr bool spec_ids_unique() {
  for (std::size_t i = 0; i < kVariantSwitchCount; ++i) {
    if (kVariantSwitches[i].spec_id == MASQ_SPEC_LOCAL_SIZE) return false;
    for (std::size_t j = 0; j < i; ++j)
      if (kVariantSwitches[i].spec_id == kVariantSwitches[j].spec_id) return false;
  }
  return true;
}
static_assert(spec_ids_unique(), "kernels/variant_table.h: specialization ids must be unique and not MASQ_SPEC_LOCAL_SIZE");

constexpr int units_of(std::string_view key) {
  for (const VariantSwitch& s : kVariantSwitches)
    if (s.key == key) return s.cpu_units;
  return -1;
}
static_assert(units_of("node_format") == MASQ_NODE_FORMAT_COUNT,
              "kernels/variant_table.h: the cpu units of MASQ_NODE_FORMAT must cover every node format");

} // namespace

std::array<std::int32_t, kVariantSwitchCount> switch_values(const KernelVariant& v) {
#define MASQ_VARIANT_VALUE(NAME, key, T, DEF, ID, units, source) v.key,
  return {MASQ_VARIANTS(MASQ_VARIANT_VALUE)};
#undef MASQ_VARIANT_VALUE
}

std::int32_t switch_value(const KernelVariant& v, std::string_view key) {
  const auto values = switch_values(v);
  for (std::size_t i = 0; i < kVariantSwitchCount; ++i)
    if (kVariantSwitches[i].key == key) return values[i];
  throw Error("kernel variant: no switch '" + std::string(key) + "' in kernels/variant_table.h");
}

} // namespace masq
