// The numerical stress suite's test cases: a cell is one primitive type at one point of
// one sweep (distance, length, radius, translation offset) or one degenerate form; it
// holds a small scene of that primitive and a mix of hard rays aimed at it. Everything
// is deterministic from the seed.
#pragma once
#include "bvh/options.h"
#include "kernels/layout.h"
#include "masq/names.h"
#include "scenes/scene.h"
#include <cstdint>
#include <string>
#include <vector>

namespace masq::stress {

enum class RayKind { Silhouette, Grazing, AxisParallel, Random, SurfaceOut, SurfaceIn, Invalid };
// In enum order: the reports index their per-kind counts by RayKind(k).
inline constexpr NameRow<RayKind> ray_kind_rows[] = {
    {RayKind::Silhouette, "silhouette", "passing just inside or outside the primitive's outline"},
    {RayKind::Grazing, "grazing", "at a shallow angle to the surface"},
    {RayKind::AxisParallel, "axis-parallel", "along a world axis"},
    {RayKind::Random, "random", "random directions near the primitive"},
    {RayKind::SurfaceOut, "surface-out", "starting on the surface, leaving it"},
    {RayKind::SurfaceIn, "surface-in", "starting on the surface, entering it"},
    {RayKind::Invalid, "nan/inf", "NaN or infinite components, zero direction, empty interval"},
};
inline constexpr NameTable ray_kind_table{"ray kind", ray_kind_rows};
inline constexpr int kRayKinds = int(ray_kind_table.size());
static_assert([] {
  for (int k = 0; k < kRayKinds; ++k)
    if (ray_kind_rows[k].value != RayKind(k)) return false;
  return true;
}());
inline const char* ray_kind_name(RayKind k) { return ray_kind_table.name(k); }

// The sweeps a cell belongs to (CellSpec::sweep; `masq stress --sweep` selects among them).
inline const std::vector<std::string>& sweep_names() {
  static const std::vector<std::string> names = {"distance", "length", "radius", "offset",
                                                 "camera",   "degenerate", "shape", "invalid"};
  return names;
}

struct CellSpec {
  PrimType type = PrimType::Capsule;
  std::string sweep;        // one of sweep_names() (shape: curves only)
  std::string label;        // e.g. "D/r=1e4"
  double radius = 1e-3;     // primitive radius (scene scale ~1)
  double length_r = 100;    // length / radius (capsule, cone, curve chord, triangle edge)
  double distance_r = 1e3;  // ray origin distance from the primitive / radius
  double offset = 0;        // translation of the whole scene (world coordinates)
  // Perspective camera: every ray starts at one eye point distance_r radii from the
  // first primitive's centre and fans over it (the other sweeps: parallel-ish rays,
  // each from its own origin distance_r radii before its aim point).
  bool camera = false;
  std::string degenerate;   // zero-length, zero-radius, coincident, contained, flat-tangent; curve shapes: bend, cusp, fold
  CurveIsect curve_isect = CurveIsect::Phantom; // curves: the intersector traced (a cell per one)
  // The cell's rays come from the seed and this index: the curve intersectors' cells of
  // one sweep point share it, so they are asked the same rays.
  std::size_t ray_seed = 0;
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
                                 PrimType::Triangle, PrimType::Ribbon};
  std::uint64_t seed = 7;
  std::vector<std::string> sweeps; // only these sweeps (distance, length, ...); empty: all
  std::vector<CurveIsect> curve_isects = {CurveIsect::Phantom, CurveIsect::Roving}; // curve cells: one per
  // Only the cells of these types out of the whole list (empty: all), each with the rays
  // it has in the whole run: the ctests run the suite a type at a time, side by side.
  std::vector<PrimType> only_types;
  // And of those, only the cells whose rays' seed (their place in the whole list) is
  // shard_index modulo shard_count: a type's cells in parts (the curve intersectors'
  // cells of the same rays stay together, sharing the oracle's answers).
  int shard_count = 1, shard_index = 0;
};

std::vector<CellSpec> sweep_cells(const SweepOptions& opt);
// Builds the scene and rays of a cell (the oracle is used to place surface-start rays).
Cell make_cell(const CellSpec& spec, int rays, std::uint64_t seed);

} // namespace masq::stress
