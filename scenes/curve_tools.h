// Scene rewrites for curves: pre-subdivision (each cubic split into k pieces, the
// masquerade paper's 1/2/4/8 "subdivisions", tighter boxes per piece) and
// approximation by linear segments (the error mode's cheap alternative to cubics).
#pragma once
#include "scenes/scene.h"

namespace masq {

// Every curve becomes k curves (de Casteljau in double, k >= 1). The swept-ball
// surface is unchanged up to the fp32 rounding of the new control points.
Scene subdivide_curves(const Scene& scene, int k);

// Every curve becomes n linear pieces between points of the curve, as capsules or
// round cones (type must be Capsule or RoundCone; n >= 1).
Scene curves_to_segments(const Scene& scene, int n, PrimType type);

// A point of a cubic Bezier curve (double precision).
glm::dvec3 bezier_point(const CurvePrim& c, double s);

} // namespace masq

namespace masq {
// The reverse for loaded strand models: every capsule or round-cone geometry whose
// segments chain into polylines (segment i ends where segment i+1 starts, in order, as
// the strand loaders write them) becomes Catmull-Rom cubic curves through the same
// points, one curve per segment (strands_to_geometry's Curve form). Other geometries
// are kept as they are.
Scene segments_to_curves(const Scene& scene);

// The strand of each primitive of a geometry whose type has an axis (scene_prim_row's
// `oriented`: capsules, round cones, curves), numbered from 0 in order: primitive i + 1
// is in primitive i's strand when it starts where i ends (its first hull ball's centre is
// i's last one's), the chaining segments_to_curves reads. Other types: empty.
std::vector<std::uint32_t> strand_ids(const Geometry& g);
} // namespace masq
