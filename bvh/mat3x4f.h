// An affine map as GPU records store it: fp32, row-major 3x4 (kernels/layout.h,
// Instance::world_to_object). A header of its own so that bvh/bounds/obb.h and
// bvh/packed_scene.h share it without including each other.
#pragma once
#include <array>

namespace masq {
using Mat3x4f = std::array<float, 12>;
} // namespace masq
