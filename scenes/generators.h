// Embedded scenes that need no data files.
#pragma once
#include "scenes/scene.h"
#include <cstdint>

namespace masq {

// The masquerade paper's synthetic bundle: `count` parallel capsules of length 1 and
// radius `radius`, axes spread uniformly over a disc of radius 0.5 (the bundle), the
// bundle's axis tilted by `tilt_deg` from +Y towards +X (in the X-Y plane).
// prim: each strand as a capsule (the paper), a round cone (radius r at the bottom,
// r/2 at the top), a cubic curve (the same strand with a gentle S-bend of 5% of its
// length), or 8 spheres of radius 3r strung along it.
struct BundleParams {
  int count = 1000;
  float radius = 0.002f;
  double tilt_deg = 45.0;
  std::uint64_t seed = 1;
  PrimType prim = PrimType::Capsule;
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
// Round cones with independent end radii in [min_radius, max_radius]; every 8th has one
// end ball containing the other.
Geometry make_random_cones(int count, float min_radius, float max_radius, double extent, std::uint64_t seed);
Geometry make_random_spheres(int count, float min_radius, float max_radius, double extent, std::uint64_t seed);
// Hair-like cubic Bezier curves: gently bent, length up to extent/2 and at least 20 radii.
Geometry make_random_curves(int count, float min_radius, float max_radius, double extent, std::uint64_t seed);

// One geometry of `type` (capsule, round cone, sphere or curve), for tests and the
// default scene variants; triangles give make_random_mesh.
Geometry make_random_geometry(PrimType type, int count, float min_radius, float max_radius, double extent,
                              std::uint64_t seed);

} // namespace masq
