// Tractography streamlines: TrackVis .trk and MRtrix .tck.
//
// Each streamline of m points becomes m-1 primitives of LoadOptions::strand_type:
// Capsule (default) or RoundCone (both radii equal); any other type is an error. The
// radius is LoadOptions::radius when > 0, else kDefaultTrackRadius (0.1 mm) with one
// warning through LoadOptions::warn. Streamlines of 0 or 1 point produce nothing.
//
// .trk (TrackVis): 1000-byte header ("TRACK\0", dim @6, voxel_size @12, n_scalars @36,
// n_properties @238, vox_to_ras @440 (version 2), voxel_order @948, n_count @988,
// version @992 (1..3 accepted), hdr_size @996 == 1000), then per streamline i32 m,
// m*(3+n_scalars) f32, n_properties f32. Either byte order: a file whose hdr_size reads
// 1000 only byte-swapped is read swapped throughout (header, counts, coordinates).
// Stored points are in "voxmm" (voxel index * voxel_size, origin at the corner of voxel
// 0). Where the header has a vox_to_ras ([3][3] nonzero; version 1 has none) they are
// returned in RAS+ world mm as nibabel.streamlines / dipy compute it:
//   world = vox_to_ras * reorient(voxmm / voxel_size - 0.5),
// where reorient maps the axes named by voxel_order (empty: LPS, with a warning) onto
// those of vox_to_ras (an axis running the other way becomes dim - 1 - v), so a .trk and
// a .tck of the same tracts overlay. Without a vox_to_ras the points stay in voxmm, with
// one warning. n_count 0 means "unknown": streamlines are read to the end of the file.
// Bytes after n_count streamlines are ignored with a warning.
//
// .tck (MRtrix): text header "mrtrix tracks", "key: value" lines, "END", read as MRtrix
// reads it: text from a '#' on is a comment, whitespace around keys and values is
// dropped, a line without "key:" is skipped (with a warning; MRtrix has no continuation
// lines), the keys datatype and file match in any case and the last of each counts
// (a changed value gets a warning), other repeated keys are joined by MRtrix, so a
// repeated "count" is not checked (warning). "datatype:" Float32LE, Float32BE, Float64LE
// or Float64BE (any case); "file: . <offset>" (data in the same file). Data are xyz
// triplets; a NaN triplet ends a streamline, an Inf triplet ends the data. Points are in
// scanner (RAS+) mm, returned as stored. A missing Inf terminator is accepted with a
// warning; a "count:" that disagrees with the data gets a warning.
//
// Errors (masq::Error "<file>: offset <o>: ..." or "<file>:<line>: ..." in the .tck
// header): wrong magic, bad header size or version, negative counts, a point count that
// is negative or exceeds the bytes left, truncation, non-finite coordinates (partial
// NaN/Inf triplets in .tck; .trk points that vox_to_ras carries past the float range),
// a vox_to_ras that is singular or not finite, a voxel_size that is not positive or a
// voxel_order that is not three of L/R, P/A, I/S when a vox_to_ras is applied (and a
// dim that is not positive on an axis it reverses), unsupported datatype, missing
// END/datatype/file keys.
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
