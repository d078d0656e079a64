// Wavefront OBJ loader (via tinyobjloader).
//
// What becomes what:
//  - v x y z [w | r g b]: vertex positions (only x, y, z are used).
//  - f: faces -> triangles (tinyobjloader triangulates polygons; relative, i.e.
//    negative, indices are resolved). Faces from every group/object go into one
//    triangle geometry.
//  - l: polylines -> one strand segment per consecutive vertex pair, a CapsulePrim or a
//    RoundConePrim by LoadOptions::strand_type. Radius: LoadOptions::radius when > 0;
//    else the default 0.002 x the diagonal of the bounding box of all vertices (1e-3
//    when that is 0), reported through LoadOptions::warn.
//  - p (points), normals, texture coordinates, groups and materials are ignored; a
//    missing or unreadable .mtl is not an error (tinyobjloader's warning is forwarded).
// A file with faces gives a triangle geometry, one with lines a strand geometry, one
// with both gives both (triangles first), each instanced once.
// Errors (masq::Error) name the source and, where known, the line: tinyobjloader parse
// errors, NaN/Inf (or beyond-float) coordinates (naming the 1-based OBJ vertex number),
// vertex indices out of range, and a file with no faces and no lines.
#pragma once
#include "scenes/loaders/loader.h"

namespace masq {

Scene load_obj(const std::string& path, const LoadOptions& opt = {});
Scene load_obj(std::span<const std::byte> data, const std::string& name, const LoadOptions& opt = {});

} // namespace masq
