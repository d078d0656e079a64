// The kernels' primitive arrays of a packed scene: one member per PRIM row of
// kernels/scene_array_table.h, named as the row, of the row's kernel struct. The member
// comes from the table row, so a new primitive type adds no member here or in PackedScene
// (bvh/packed_scene.h inherits this); its row of scenes/prim_table.cpp packs into it.
#pragma once
#include "kernels/layout.h"
#include "kernels/scene_array_table.h"
#include "scenes/huge_page_vector.h"
#include <vector>

namespace masq {

struct KernelPrimArrays {
#define MASQ_PRIM_ARRAY_SCENE(T, name)
#define MASQ_PRIM_ARRAY_NODES(T, name)
#define MASQ_PRIM_ARRAY_BV(T, name)
#define MASQ_PRIM_ARRAY_PRIM(T, name) HugePageVector<kernel::T> name; /* scenes/huge_page_vector.h */
#define MASQ_PRIM_ARRAY_ROW(T, name, binding, kernels, source) MASQ_PRIM_ARRAY_##source(T, name)
  MASQ_SCENE_ARRAYS(MASQ_PRIM_ARRAY_ROW)
#undef MASQ_PRIM_ARRAY_ROW
#undef MASQ_PRIM_ARRAY_PRIM
#undef MASQ_PRIM_ARRAY_BV
#undef MASQ_PRIM_ARRAY_NODES
#undef MASQ_PRIM_ARRAY_SCENE
};

} // namespace masq
