// The scenes layer's table of primitive types: what a Geometry of each type holds and how
// the scene model counts, checks and bounds it. Code that would ask "which type is this?"
// calls through the row (scene_prim_row) or reads one of its columns instead, so a new
// type is one new row here (docs/architecture.md, "Add a primitive intersector").
#pragma once
#include "scenes/kernel_prims.h"
#include "scenes/scene.h"
#include <array>
#include <cstddef>
#include <cstdint>
#include <string>

namespace masq {

struct Strand; // scenes/strand_generators.h

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

  // Strands: how files of polylines, the generators and the curve conversions make
  // primitives of this type. nullptr where the type is not made that way.
  //
  // Appends the segment from ball (a, ra) to ball (b, rb) as one primitive (a capsule of
  // the mean radius 0.5 (ra + rb), a round cone with both radii). The rows that have one
  // are the strand types a loader accepts (require_strand_type).
  void (*add_segment)(Geometry&, const glm::vec3& a, float ra, const glm::vec3& b, float rb);
  void (*reserve)(Geometry&, std::size_t n); // room for n more primitives in its array
  // Appends segment i (points i, i + 1) of a polyline with per-point radii: add_segment,
  // or for a curve the Catmull-Rom piece through the points (end points repeated) as a
  // cubic Bezier of the mean radius (strands_to_geometry).
  void (*add_strand_piece)(Geometry&, const Strand&, std::size_t i);
  // One strand of the masquerade bundle (make_bundle) along the axis a -> b of radius r:
  // a capsule; a round cone of r at a, r/2 at b; a curve with an S-bend of `bend`; eight
  // balls of radius 3r strung along it. nullptr: the type cannot be a bundle strand.
  void (*add_bundle_strand)(Geometry&, const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& bend, float r);
  // A random geometry of this type (scenes/generators.h, make_random_geometry).
  Geometry (*random)(int count, float min_radius, float max_radius, double extent, std::uint64_t seed);

  // The kernels: how the type becomes its array of kernels/layout.h structs. These were a
  // separate bvh-layer row (bvh/prim_rows.cpp); they live here, beside the balls they
  // mirror, because they need nothing of the bvh layer (the array is a KernelPrimArrays
  // member, generated from the scene array table), so a new type has one row less.
  int kernel_type;     // its MASQ_PRIM_* id (row i has id i; prim_table.cpp checks it)
  // The intersector's cost relative to a capsule's: the structure cost model and the SAH
  // price of builders that price intersections (bvh/twolevel/structure_cost.h).
  double isect_factor;
  // Its robust intersector's crossing does not depend on the search window's far end and
  // is taken exactly when it lies within it, so a walk may meet such primitives in any
  // order and still end on the same nearest hit: the cpu's packets take them
  // (kernels/packet_walk_cpp.h). Not the triangle (a scaled comparison); the others not
  // argued yet.
  bool order_free;
  // Appends g's primitives (fp32) to its array in `out`; returns the index of the first.
  int (*pack)(const Geometry& g, KernelPrimArrays& out);
  // The hull balls of element `index` of its array in `packed` (a triangle: its vertices),
  // as balls() gives them for the primitive it was packed from.
  int (*kernel_balls)(const KernelPrimArrays& packed, std::size_t index, PrimBalls& out);
  std::size_t (*kernel_bytes)(const KernelPrimArrays& packed); // its array's bytes
};

// The row of type t (rows are in enum order: scenes/prim_table.cpp static_asserts it).
const ScenePrimRow& scene_prim_row(PrimType t);

// The row of a MASQ_PRIM_* id (a kernel::Geometry's type); throws masq::Error for none.
const ScenePrimRow& scene_prim_row_of_kernel_type(int kernel_type);

// The names of the types that strands can be loaded as (rows with add_segment), plural,
// joined by " or ": "capsules or round cones", for messages.
std::string strand_type_names();

// The largest ball radius of primitive `prim` (0 for a triangle).
float prim_max_radius(const Geometry& g, std::size_t prim);

} // namespace masq
