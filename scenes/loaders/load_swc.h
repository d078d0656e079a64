// SWC neuron morphologies (text lines "id type x y z radius parent", '#' comments).
//
// Every non-root sample and its parent make one RoundConePrim (a = parent position and
// radius, b = sample position and radius): SWC always produces round cones, whatever
// LoadOptions::strand_type says, because the varying radius along a neurite is the point
// of the format. LoadOptions::radius, when > 0, scales every radius. Coordinates and
// radii are kept in the file's units (micrometres for NeuroMorpho.Org files).
//
// Accepted: ids with gaps, several roots (parent -1, or any negative parent), parents
// listed after their children (resolved once all lines are read), CRLF line ends, extra
// columns after the seventh (ignored). An isolated root (no children) produces nothing;
// a root's soma radius only shows up through the round cones that touch it.
// Repaired with one warning per file through LoadOptions::warn: negative radii (made
// positive; one real NeuroMorpho file has many -0.275 / -0.14 radii).
// Errors (masq::Error "<file>:<line>: ..."): fewer than 7 fields, a non-numeric field,
// non-integer id/type/parent, NaN/Inf coordinates or radius, a duplicate id, a parent id
// that does not exist, a sample that is its own parent, and a file with no segment.
#pragma once
#include "scenes/loaders/loader.h"
#include <span>
#include <string>

namespace masq {

Scene load_swc(const std::string& path, const LoadOptions& opt = {});
Scene load_swc(std::span<const std::byte> data, const std::string& name, const LoadOptions& opt = {});

} // namespace masq
