// The numerical stress suite's test cases: a cell is one primitive type at one point of
// one sweep (distance, length, radius, translation offset) or one degenerate form; it
// holds a small scene of that primitive and a mix of hard rays aimed at it. Everything
// is deterministic from the seed.
#pragma once
#include "kernels/layout.h"
#include "scenes/scene.h"
#include <cstdint>
#include <string>
#include <vector>

namespace masq::stress {

enum class RayKind { Silhouette, Grazing, AxisParallel, Random, SurfaceOut, SurfaceIn, Invalid };
inline constexpr int kRayKinds = 7;
const char* ray_kind_name(RayKind k);

struct CellSpec {
  PrimType type = PrimType::Capsule;
  std::string sweep;        // distance, length, radius, offset, degenerate, invalid
  std::string label;        // e.g. "D/r=1e4"
  double radius = 1e-3;     // primitive radius (scene scale ~1)
  double length_r = 100;    // length / radius (capsule, cone, curve chord, triangle edge)
  double distance_r = 1e3;  // ray origin distance from the primitive / radius
  double offset = 0;        // translation of the whole scene (world coordinates)
  std::string degenerate;   // zero-length, zero-radius, coincident, contained, flat-tangent
};

struct Cell {
  CellSpec spec;
  Scene scene;
  std::vector<kernel::Ray> rays;
  std::vector<RayKind> kinds;
  double radius = 0;        // the scale |dt| and distances are measured in
  // Clearance below which a ray counts as ambiguous: 4u (1 + (D + L) / r), the
  // first-order rounding of any fp32 evaluation at this distance and length.
  double ambiguity = 0;
};

struct SweepOptions {
  int rays_per_cell = 16384;
  bool quick = false; // fewer sweep points (the ctest subset)
  std::vector<PrimType> types = {PrimType::Capsule, PrimType::RoundCone, PrimType::Curve, PrimType::Sphere,
                                 PrimType::Triangle};
  std::uint64_t seed = 7;
};

std::vector<CellSpec> sweep_cells(const SweepOptions& opt);
// Builds the scene and rays of a cell (the oracle is used to place surface-start rays).
Cell make_cell(const CellSpec& spec, int rays, std::uint64_t seed);

} // namespace masq::stress
