#include "host/scene_arrays.h"

namespace masq {

namespace {

// The table's rules that the compiler can check: every row its own binding, below the
// address slots and clear of the other bindings of kernels/kernel_data.h.
constexpr bool bindings_valid() {
  for (std::size_t i = 0; i < kSceneArrayCount; ++i) {
    const std::uint32_t b = kSceneArrays[i].binding;
    if (b >= MASQ_ADDRESS_SLOTS || b == MASQ_BINDING_RAYS || b == MASQ_BINDING_HITS || b == MASQ_BINDING_STATS ||
        b == MASQ_BINDING_TLAS_PARTS || b == MASQ_BINDING_PRIM_MAP)
      return false;
    for (std::size_t j = 0; j < i; ++j)
      if (kSceneArrays[j].binding == b) return false;
  }
  return true;
}
static_assert(bindings_valid(), "kernels/scene_array_table.h: a binding is repeated, reserved or not below "
                                "MASQ_ADDRESS_SLOTS");

template <class T, class Allocator>
ArrayBytes bytes_of(const std::vector<T, Allocator>& v) {
  return {v.data(), v.size() * sizeof(T)};
}

} // namespace

SceneArrayData scene_array_data(const PackedScene& scene) {
  SceneArrayData d;
#define MASQ_SOURCE_SCENE(name) d[SceneArray::name] = bytes_of(scene.name);
#define MASQ_SOURCE_PRIM(name) MASQ_SOURCE_SCENE(name) // PackedScene inherits KernelPrimArrays
#define MASQ_SOURCE_NODES(name) d[SceneArray::name] = {scene.node_data(), scene.node_bytes()};
#define MASQ_SOURCE_BV(name)
#define MASQ_PACKED_ROW(T, name, b, kernels, source) MASQ_SOURCE_##source(name)
  MASQ_SCENE_ARRAYS(MASQ_PACKED_ROW)
#undef MASQ_PACKED_ROW
#undef MASQ_SOURCE_BV
#undef MASQ_SOURCE_NODES
#undef MASQ_SOURCE_PRIM
#undef MASQ_SOURCE_SCENE
  return d;
}

SceneArrayData scene_array_data(const BvScene& scene) {
  SceneArrayData d = scene_array_data(scene.prims);
#define MASQ_SOURCE_SCENE(name)
#define MASQ_SOURCE_PRIM(name)
#define MASQ_SOURCE_NODES(name)
#define MASQ_SOURCE_BV(name) d[SceneArray::name] = bytes_of(scene.name);
#define MASQ_BV_ROW(T, name, b, kernels, source) MASQ_SOURCE_##source(name)
  MASQ_SCENE_ARRAYS(MASQ_BV_ROW)
#undef MASQ_BV_ROW
#undef MASQ_SOURCE_BV
#undef MASQ_SOURCE_NODES
#undef MASQ_SOURCE_PRIM
#undef MASQ_SOURCE_SCENE
  return d;
}

kernel::KernelData kernel_data(const SceneArrayData& data) {
  kernel::KernelData kd{};
#define MASQ_KD_POINTER(T, name, b, kernels, source) \
  kd.name = static_cast<decltype(kd.name)>(data[SceneArray::name].data);
#define MASQ_KD_VIEW_POINTER(T, name, of) kd.name = reinterpret_cast<decltype(kd.name)>(kd.of);
  MASQ_SCENE_ARRAYS(MASQ_KD_POINTER)
  MASQ_SCENE_ARRAY_VIEWS(MASQ_KD_VIEW_POINTER)
#undef MASQ_KD_VIEW_POINTER
#undef MASQ_KD_POINTER
  return kd;
}

} // namespace masq
