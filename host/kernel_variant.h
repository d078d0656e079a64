// The kernel variant of one dispatch on the host: one value per switch of
// kernels/variant_table.h, made from the scene's KernelFeatures and the trace call. Each
// backend hands these values to its kernels through its one mechanism: Vulkan
// specialization constants, OpenCL -D options, the cpu's generated kernel units.
#pragma once
#include "bvh/packed_scene.h"
#include "kernels/variant_table.h"
#include <array>
#include <cstddef>
#include <cstdint>
#include <string_view>

namespace masq {

// What a trace call adds to the scene's features (the TRACE(...) sources of the table).
struct TraceSwitches {
  bool stats = false;   // per-ray counters wanted
  bool any_hit = false; // occlusion query: the first hit found ends the ray
};

// One value per switch, as the kernels read it (bool as 0 or 1), named by the row's key.
struct KernelVariant {
#define MASQ_VARIANT_FIELD(NAME, key, T, DEF, ID, units, source) std::int32_t key = DEF;
  MASQ_VARIANTS(MASQ_VARIANT_FIELD)
#undef MASQ_VARIANT_FIELD
  bool operator==(const KernelVariant&) const = default;
};

// The kernel's value of a host option (the table's host source column).
inline std::int32_t switch_value(bool b) { return b ? 1 : 0; }
inline std::int32_t switch_value(int i) { return i; }
inline std::int32_t switch_value(Mode m) { return m == Mode::Robust ? 1 : 0; }
inline std::int32_t switch_value(NodeFormat f) { return node_format_id(f); }

KernelVariant kernel_variant(const KernelFeatures& features, const TraceSwitches& trace);

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
