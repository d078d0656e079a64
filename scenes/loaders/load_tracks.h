// Tractography streamlines: TrackVis .trk and MRtrix .tck.
//
// Each streamline of m points becomes m-1 primitives of LoadOptions::strand_type:
// Capsule (default) or RoundCone (both radii equal); any other type is an error. The
// radius is LoadOptions::radius when > 0, else kDefaultTrackRadius (0.1 mm) with one
// warning through LoadOptions::warn. Streamlines of 0 or 1 point produce nothing.
//
// .trk: 1000-byte little-endian header ("TRACK\0", n_scalars @36, n_properties @238,
// n_count @988, version @992 (1..3 accepted), hdr_size @996 == 1000), then per
// streamline i32 m, m*(3+n_scalars) f32, n_properties f32. Coordinates are returned as
// stored: millimetres in TrackVis "voxmm" space (voxel index * voxel size, origin at the
// corner of the first voxel); vox_to_ras is not applied. n_count 0 means "unknown":
// streamlines are read to the end of the file. Bytes after n_count streamlines are
// ignored with a warning.
//
// .tck: text header "mrtrix tracks", "key: value" lines, "END"; "datatype:" Float32LE,
// Float32BE, Float64LE or Float64BE; "file: . <offset>" (data in the same file). Data are
// xyz triplets; a NaN triplet ends a streamline, an Inf triplet ends the data. Points are
// in scanner space (mm), returned as stored. A missing Inf terminator is accepted with a
// warning; a "count:" that disagrees with the data gets a warning.
//
// Errors (masq::Error "<file>: offset <o>: ..." or "<file>:<line>: ..." in the .tck
// header): wrong magic, bad header size or version, negative counts, a point count that
// is negative or exceeds the bytes left, truncation, non-finite coordinates (partial
// NaN/Inf triplets in .tck), unsupported datatype, missing END/file keys.
#pragma once
#include "scenes/loaders/loader.h"
#include <span>
#include <string>

namespace masq {

inline constexpr float kDefaultTrackRadius = 0.1f; // mm

Scene load_trk(const std::string& path, const LoadOptions& opt = {});
Scene load_trk(std::span<const std::byte> data, const std::string& name, const LoadOptions& opt = {});
Scene load_tck(const std::string& path, const LoadOptions& opt = {});
Scene load_tck(std::span<const std::byte> data, const std::string& name, const LoadOptions& opt = {});

} // namespace masq
