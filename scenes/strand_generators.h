// Embedded strand scenes (no files): hair and fur grown from a surface, streamlines of
// an analytic flow, random tubes. Deterministic from the seed.
#pragma once
#include "scenes/scene.h"
#include <cstdint>
#include <vector>

namespace masq {

// A polyline with a radius per point: what the generators grow, before it becomes
// primitives.
struct Strand {
  std::vector<glm::dvec3> points;
  std::vector<double> radii;
};

// Strands -> one geometry: Capsule (one per segment, mean radius), RoundCone (one per
// segment, per-point radii) or Curve (Catmull-Rom through the points as cubic Bezier
// pieces, mean radius per piece).
Geometry strands_to_geometry(const std::vector<Strand>& strands, PrimType type);

enum class HairSurface { Sphere, Head, Body };

struct HairParams {
  int strands = 10000;
  int points = 16;          // per strand (>= 2)
  double length = 0.4;      // strand length (surface radius 1)
  double radius = 1.5e-3;   // root radius; tips taper to half
  double curl = 0.0;        // helix radius as a fraction of the length (0: straight)
  double curl_turns = 3.0;  // helix turns along a strand
  double gravity = 1.0;     // droop towards -y (0: along the normal)
  double noise = 0.05;      // random bend
  HairSurface surface = HairSurface::Head;
  PrimType type = PrimType::Curve;
  std::uint64_t seed = 1;
};
// Hair or fur on a unit sphere (Sphere), its upper half (Head) or an ellipsoid 2x1x1
// (Body, fur). The scene also holds a camera that frames it.
std::vector<Strand> grow_hair(const HairParams& p);
Scene make_hair_scene(const HairParams& p);

struct StreamlineParams {
  int lines = 500;
  int steps = 150;          // RK4 steps per line
  double step = 0.02;
  double radius = 6e-3;
  PrimType type = PrimType::RoundCone;
  std::uint64_t seed = 1;
};
// Streamlines of the ABC (Arnold-Beltrami-Childress) flow, seeded in the cube
// [-1,1]^3; the radius shrinks with the local speed (thin where the flow is fast).
std::vector<Strand> trace_streamlines(const StreamlineParams& p);
Scene make_streamline_scene(const StreamlineParams& p);

// Random-walk tubes with varying radius (round cones), for tests and benchmarks.
std::vector<Strand> make_random_tubes(int count, int points, double radius, std::uint64_t seed);

} // namespace masq
