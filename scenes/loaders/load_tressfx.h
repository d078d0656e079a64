// AMD TressFX hair assets (.tfx), versions 3 and 4; the version is read from the header.
//
// TressFX 3: 296-byte header (f32 version 3.x, u32 numStrands, u32 vertsPerStrand,
// u32 numFollow, i32 bothEndsImmovable, u32 reserved[31], then at byte 144 the offsets
// of positions (f32x3 per vertex), per-strand thickness, strand UV, vertex colour, guide
// and vertex UV). TressFX 4: 160-byte header (f32 version 4.x, u32 numStrands,
// u32 vertsPerStrand, offsets of positions (f32x4 per vertex, w = movability, ignored),
// strand UV, vertex UV, per-strand thickness, colour). Only guide strands are stored
// (follow strands are generated at run time by TressFX) and only they are loaded.
//
// Each strand of n vertices becomes n-1 segments: CapsulePrim (LoadOptions::strand_type
// == Capsule, radius = mean of the two point radii) or RoundConePrim (RoundCone).
// Zero-length segments are kept (a zero-length capsule is a sphere).
//
// Radius: TressFX stores no absolute width. The base radius is LoadOptions::radius when
// > 0, else 1e-3 x the diagonal of the strands' bounding box (reported through
// LoadOptions::warn). When the file has a per-strand thickness array (offset != 0) its
// value is a coefficient (as in TressFX's renderer): radius = thickness * base radius.
// A negative thickness is repaired to its absolute value with a warning; a NaN/Inf one
// is an error.
//
// Errors (masq::Error naming the source and byte offset): truncated header or arrays,
// unsupported version, zero strands, fewer than 2 vertices per strand, counts larger
// than the file, offsets inside the header or outside the file, NaN/Inf coordinates
// (naming strand and vertex).
#pragma once
#include "scenes/loaders/loader.h"

namespace masq {

Scene load_tressfx(const std::string& path, const LoadOptions& opt = {});
Scene load_tressfx(std::span<const std::byte> data, const std::string& name, const LoadOptions& opt = {});

} // namespace masq
