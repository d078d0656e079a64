// Cem Yuksel's .hair format (http://www.cemyuksel.com/research/hairmodels/).
//
// 128-byte header: char[4] "HAIR", u32 strands, u32 points, u32 flags,
// u32 default_segments, f32 default_thickness, f32 default_transparency,
// f32[3] default_color, char[88] info. Flag bits: 1 segments array (u16 per strand),
// 2 points (f32x3), 4 thickness (f32 per point), 8 transparency (f32 per point),
// 16 colour (f32x3 per point); the arrays follow in that order. Without the segments
// array every strand has default_segments segments; without the thickness array every
// point has default_thickness.
//
// Loading: strand i of s segments (s+1 points) becomes s primitives: CapsulePrim
// (LoadOptions::strand_type == Capsule, radius = mean of the two point radii) or
// RoundConePrim (RoundCone, per-point radii). Zero-length segments are kept (spheres);
// strands of 0 segments give no primitive. Thickness is a diameter in scene units:
// radius = thickness / 2 (LoadOptions::radius is then ignored). A negative thickness is
// repaired to its absolute value with a warning. When the file has no thickness array
// and default_thickness is 0 or not finite, the radius is LoadOptions::radius if > 0,
// else 1e-3 x the strands' bounding-box diagonal (with a warning). Points beyond those
// the strands use are ignored with a warning.
//
// Errors (masq::Error naming the source and byte offset): truncated header or arrays,
// wrong magic, no points array, zero strands, counts larger than the file, segments
// needing more points than the file has, NaN/Inf coordinates or thickness (naming
// strand and point).
//
// Writing: the scene's capsule and round-cone geometries (instances must have identity
// transforms; a scene without instances writes every geometry) become strands: consecutive
// segments whose endpoint and radius match the next one's start (bit for bit) form one
// strand, so reading the file back with the same strand_type gives the same primitives
// bit for bit. Thickness = 2 * radius per point; the thickness array is omitted when
// every radius is the same positive value, the segments array when every strand has the
// same segment count. Strands longer than 65535 segments are split. Other primitive
// types, transformed instances and scenes without strands throw masq::Error.
#pragma once
#include "scenes/loaders/loader.h"

namespace masq {

Scene load_hair(const std::string& path, const LoadOptions& opt = {});
Scene load_hair(std::span<const std::byte> data, const std::string& name, const LoadOptions& opt = {});

std::vector<std::byte> write_hair(const Scene& scene);
void save_hair(const Scene& scene, const std::string& path);

} // namespace masq
