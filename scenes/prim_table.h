// The scenes layer's table of primitive types: what a Geometry of each type holds and how
// the scene model counts, checks and bounds it. Code that would ask "which type is this?"
// calls through the row (scene_prim_row) or reads one of its columns instead, so a new
// type is one new row here (docs/architecture.md, "Add a primitive intersector").
#pragma once
#include "scenes/scene.h"
#include <array>
#include <cstddef>

namespace masq {

// One ball of a primitive's hull: every primitive is contained in the convex hull of at
// most four of them (a triangle: its vertices, radius 0).
struct PrimBall {
  glm::vec3 centre;
  float radius;
};
using PrimBalls = std::array<PrimBall, 4>;

// The solid a primitive's balls describe: what clipping and OBB fitting work on.
enum class PrimShape {
  Triangle, // three vertices (radius 0): the flat triangle
  Segment,  // two balls and the hull between them (capsule: equal radii; round cone)
  Ball,     // one ball
  Bezier,   // four control balls of equal radius: a cubic Bezier swept by a ball
};

struct ScenePrimRow {
  PrimType type;
  // Columns: properties code asks of a type, rather than comparing types.
  bool mesh;     // indexed triangles over shared vertices: no radius, no ball hull
  bool oriented; // a primitive has an axis (capsule, round cone, curve): strands, clusters
  PrimShape shape;
  // The strand type a file of strands is loaded as to make strands of this type: a curve
  // is made from round cones (keeping per-point radii), a type without strands from
  // capsules (the loaders' default).
  PrimType strand_file_type;
  const char* singular; // how messages name one primitive ("round cone 3")
  std::size_t (*count)(const Geometry&);
  bool (*holds_any)(const Geometry&); // its array is not empty (whatever g.type says)
  // Throws masq::Error naming geometry g and the primitive: non-finite points, indices
  // beyond the vertices, negative or NaN radii.
  void (*validate)(const Geometry&, std::size_t g);
  // The hull balls of primitive `prim` (no range check beyond the arrays' .at()); returns
  // how many of `out` it filled.
  int (*balls)(const Geometry&, std::size_t prim, PrimBalls& out);
};

// The row of type t (rows are in enum order: scenes/prim_table.cpp static_asserts it).
const ScenePrimRow& scene_prim_row(PrimType t);

// The largest ball radius of primitive `prim` (0 for a triangle).
float prim_max_radius(const Geometry& g, std::size_t prim);

} // namespace masq
