// The stress suite's table of primitive types: how a cell places one primitive of each
// type, which degenerate and shape cells a type gets, and how rays are aimed at it. The
// suite calls through the row (stress_prim_row) rather than asking "which type is this?",
// so a new type is one new row here (docs/architecture.md, "The tables").
#pragma once
#include "scenes/scene.h"
#include "stress/stress_cases.h"
#include "stress/stress_random.h"
#include <array>
#include <span>

namespace masq::stress {

// What the ray generators need of a primitive: its control points in double (rounded
// through fp32 first: the points the scene holds) and its radii.
struct Probe {
  PrimType type;
  std::array<glm::dvec3, 4> p{};
  double ra = 0, rb = 0;
  // A core point, the unit tangent and the radius at parameter s in [0,1] (sphere: its
  // centre; triangle: a point on the edge p0 p1). Through the type's row.
  glm::dvec3 point(double s) const;
  glm::dvec3 tangent(double s) const;
  double radius(double s) const;
};

// Where the cell puts one primitive: drawn by the builder, the same for every type, so a
// row adds the primitive without drawing anything.
struct PrimPlace {
  glm::dvec3 centre;
  glm::dvec3 w, m;   // unit axis and a unit perpendicular
  glm::dvec3 a, e;   // the axis' ends, centre -/+ len/2 w (len 0 for "zero-length")
  double r, L;       // the cell's radius and length
  float rf;          // the radius the primitive gets (0 for "zero-radius")
};

// A point and direction for one ray of a kind aimed at a probe (world, double).
struct Aim {
  glm::dvec3 point, dir;
};

// What aiming needs of the cell besides the probe.
struct AimFrom {
  double L;               // the cell's length
  const glm::dvec3* eye;  // camera cells: the eye every ray starts at; else null
  double spread;          // how far from the core random and axis-parallel rays pass, in radii
};

struct StressPrimRow {
  PrimType type;
  // The "degenerate" cells of this type, in report order, and the "shape" cells (solids
  // that are not a tube about a smooth axis).
  std::span<const char* const> degenerates, shapes;
  // Its size is its length, not a radius (a triangle): the band's unit and the surface
  // step scale with L.
  bool sized_by_length;
  // The cell is asked once per curve intersector (the same rays each time).
  bool per_curve_isect;
  // Appends the primitive at `at` to g (degenerate cells per c.degenerate) and fills its probe.
  void (*add)(const CellSpec& c, const PrimPlace& at, Geometry& g, Probe& pr);
  glm::dvec3 (*point)(const Probe&, double s);
  glm::dvec3 (*axis)(const Probe&, double s); // the tangent before normalising (may be 0)
  double (*radius)(const Probe&, double s);
  // What a camera looks at and the axis it looks across (0: none, any direction will do).
  glm::dvec3 (*centre)(const Probe&);
  glm::dvec3 (*chord)(const Probe&);
  // A ray of `kind` at pr (kinds that choose their own direction are not asked with an eye).
  Aim (*aim)(const Probe& pr, RayKind kind, const AimFrom& from, Rng& rng);
};

// The row of type t (rows are in enum order: stress_prim_rows.cpp static_asserts it).
const StressPrimRow& stress_prim_row(PrimType t);

} // namespace masq::stress
