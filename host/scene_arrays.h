// The scene arrays of kernels/scene_array_table.h on the host: each row's name, binding
// and element size, which kernels read it, where its data lives, and the cpu's pointers
// to it. The backends upload, bind and pass the arrays by walking these rows; none
// names an array.
#pragma once
#include "bvh/bv/bv_scene.h"
#include "bvh/packed_scene.h"
#include "kernels/kernel_data.h"
#include <array>
#include <cstddef>
#include <cstdint>
#include <string_view>
#include <type_traits>

namespace masq {

// The rows, in table order (the order of the OpenCL kernels' parameters).
enum class SceneArray : std::uint32_t {
#define MASQ_SCENE_ARRAY_ENUM(T, name, b, kernels, source) name,
  MASQ_SCENE_ARRAYS(MASQ_SCENE_ARRAY_ENUM)
#undef MASQ_SCENE_ARRAY_ENUM
};

// The kernels that read a row (the table's kernels column).
enum class KernelFamily { TwoLevel, Bv };

struct SceneArrayInfo {
  std::string_view name;     // as the kernels name it
  std::uint32_t binding;     // Vulkan binding and address slot
  std::size_t element_bytes; // one element
  bool two_level, bv;        // read by the two-level kernels / the bv kernels
  constexpr bool read_by(KernelFamily f) const { return f == KernelFamily::TwoLevel ? two_level : bv; }
};

namespace scene_array_detail {
inline constexpr bool kTWO_LEVEL[2] = {true, false};
inline constexpr bool kBV[2] = {false, true};
inline constexpr bool kBOTH[2] = {true, true};
} // namespace scene_array_detail

#define MASQ_SCENE_ARRAY_INFO(T, name, b, kernels, source)                                          \
  SceneArrayInfo{#name, b, sizeof(std::remove_pointer_t<decltype(kernel::KernelData::name)>),                \
                 scene_array_detail::k##kernels[0], scene_array_detail::k##kernels[1]},
inline constexpr std::array kSceneArrays{MASQ_SCENE_ARRAYS(MASQ_SCENE_ARRAY_INFO)};
#undef MASQ_SCENE_ARRAY_INFO
inline constexpr std::size_t kSceneArrayCount = kSceneArrays.size();

constexpr const SceneArrayInfo& info(SceneArray a) { return kSceneArrays[static_cast<std::size_t>(a)]; }

// One row's data on the host (empty: the array has no elements, or the scene has none).
struct ArrayBytes {
  const void* data = nullptr;
  std::size_t bytes = 0;
};
// The data of every row, by SceneArray.
struct SceneArrayData {
  std::array<ArrayBytes, kSceneArrayCount> rows{};
  ArrayBytes& operator[](SceneArray a) { return rows[static_cast<std::size_t>(a)]; }
  const ArrayBytes& operator[](SceneArray a) const { return rows[static_cast<std::size_t>(a)]; }
};

// The rows a PackedScene holds (the table's SCENE and NODES sources; BV rows empty).
SceneArrayData scene_array_data(const PackedScene& scene);
// The rows a BvScene holds: its primitives' (from scene.prims) and its hierarchy's.
SceneArrayData scene_array_data(const BvScene& scene);

// The cpu kernels' pointers to the data (which must outlive them).
kernel::KernelData kernel_data(const SceneArrayData& data);

} // namespace masq
