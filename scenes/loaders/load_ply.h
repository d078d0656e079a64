// PLY (Stanford polygon file) loader: "format ascii 1.0", "binary_little_endian 1.0" and
// "binary_big_endian 1.0"; all scalar types (char/int8 ... double/float64) and list
// properties.
//
// What becomes what:
//  - element vertex: properties x, y, z (required when vertices are used), optional
//    radius; other properties are read and ignored.
//  - element face: list vertex_indices (or vertex_index) -> triangles; polygons with
//    more than 3 vertices are fan-triangulated (v0 v[i] v[i+1]). Fewer than 3: error.
//  - element edge: vertex1, vertex2 -> one strand segment each, a CapsulePrim or a
//    RoundConePrim by LoadOptions::strand_type. Radius: the vertex property `radius`
//    when present (a capsule takes the mean of its two ends; a negative radius is made
//    positive with a warning); else LoadOptions::radius when > 0; else the default
//    0.002 x the diagonal of the bounding box of all vertices (1e-3 when that is 0).
//  - other elements are skipped (read, so binary offsets stay right).
// A file with faces gives a triangle geometry, one with edges a strand geometry, one
// with both gives both (triangles first), each instanced once.
// Errors (masq::Error) name the source and the header line, the data line (ASCII) or
// the byte offset (binary).
#pragma once
#include "scenes/loaders/loader.h"

namespace masq {

Scene load_ply(const std::string& path, const LoadOptions& opt = {});
Scene load_ply(std::span<const std::byte> data, const std::string& name, const LoadOptions& opt = {});

} // namespace masq
