// Specialization constants applied by masq before the driver sees a module.
// The kernels carry every primitive type, node format and query, each behind a
// specialization constant (kernels/variant_table.h). Given the constants, a driver keeps
// only the code they leave live, but it translates the whole module first: lavapipe
// spends most of a pipeline's creation in NIR passes over code the variant never runs
// (a capsule-only trace kernel is a fifth of the module), and its disk cache keeps only
// the machine code, so every process pays them again (a small test: 3.1 s -> 1.2 s).
// Freezing the constants and dropping the dead code here gives every driver the variant
// alone. Only control flow and unused definitions are removed: no arithmetic is folded,
// so every result keeps its bits.
#pragma once
#include <cstdint>
#include <span>
#include <vector>

namespace masq::vk {

// `spirv` with each specialization constant of SpecId i < values.size() given values[i]
// (bools: 0 false, else true) and turned into a constant, then the branches those
// constants decide and the code and functions no longer reached removed (constants stay:
// the work-group size is one that only a decoration uses). Constants with no value stay
// specialization constants. Throws masq::Error with the optimizer's messages for words
// it cannot read as a module.
std::vector<std::uint32_t> with_constants_frozen(std::span<const std::uint32_t> spirv,
                                                 std::span<const std::uint32_t> values);

// Whether MASQ_VK_SPECIALIZE (host|driver, default host) asks for with_constants_frozen
// at module creation; driver passes the compiled module and VkSpecializationInfo as they
// are. Throws masq::Error for another value.
bool specialize_on_host();

} // namespace masq::vk
