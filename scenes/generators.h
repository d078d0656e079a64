// Embedded scenes that need no data files.
#pragma once
#include "scenes/scene.h"
#include <cstdint>

namespace masq {

// The masquerade paper's synthetic bundle: `count` parallel capsules of length 1 and
// radius `radius`, axes spread uniformly over a disc of radius 0.5 (the bundle), the
// bundle's axis tilted by `tilt_deg` from +Y towards +X (in the X-Y plane).
struct BundleParams {
  int count = 1000;
  float radius = 0.002f;
  double tilt_deg = 45.0;
  std::uint64_t seed = 1;
};
Geometry make_bundle(const BundleParams& p);

// A square of two triangles in the plane y = height, side 2*half_size.
Geometry make_ground_plane(double height, double half_size);

// The default scene: the paper's bundle (N=1000, r=0.002, tilt 45 deg) over a triangle
// ground plane, with a camera that frames both.
Scene make_default_scene(const BundleParams& p = {});

// Random test scenes (deterministic from the seed).
Geometry make_random_capsules(int count, float min_radius, float max_radius, double extent, std::uint64_t seed);
Geometry make_random_mesh(int triangles, double extent, std::uint64_t seed); // a bumpy grid sheet

} // namespace masq
