// The kernel variant of one dispatch on the host: one value per switch of
// kernels/variant_table.h (made from the scene and the trace call by kernel_variant,
// host/scene_variant.h). Each backend hands these values to its kernels through its one
// mechanism: Vulkan specialization constants, OpenCL -D options, the cpu's generated
// kernel units. A light header: every cpu kernel unit includes it.
#pragma once
#include "kernels/variant_table.h"
#include <array>
#include <cstddef>
#include <cstdint>
#include <string_view>

namespace masq {

// One value per switch, as the kernels read it (bool as 0 or 1), named by the row's key.
struct KernelVariant {
#define MASQ_VARIANT_FIELD(NAME, key, T, DEF, ID, units, source) std::int32_t key = DEF;
  MASQ_VARIANTS(MASQ_VARIANT_FIELD)
#undef MASQ_VARIANT_FIELD
  bool operator==(const KernelVariant&) const = default;
};

// A row of the table as the host sees it.
struct VariantSwitch {
  std::string_view name; // as the kernels read it (MASQ_STATS)
  std::string_view key;  // KernelVariant member
  std::uint32_t spec_id; // Vulkan specialization constant id
  int cpu_units;         // 0: read at run time; 1: fixed; n >= 2: one cpu unit per value
};
#define MASQ_VARIANT_ROW(NAME, key, T, DEF, ID, units, source) VariantSwitch{#NAME, #key, ID, units},
inline constexpr std::array kVariantSwitches{MASQ_VARIANTS(MASQ_VARIANT_ROW)};
#undef MASQ_VARIANT_ROW
inline constexpr std::size_t kVariantSwitchCount = kVariantSwitches.size();

// The values of v in row order (kVariantSwitches).
std::array<std::int32_t, kVariantSwitchCount> switch_values(const KernelVariant& v);
// The value of the row with this key; throws masq::Error for a key of no row.
std::int32_t switch_value(const KernelVariant& v, std::string_view key);

} // namespace masq
