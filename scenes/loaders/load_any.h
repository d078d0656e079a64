// Load a scene file by its extension: .tfx (TressFX 3/4), .hair (Cem Yuksel), .swc,
// .trk (TrackVis), .tck (MRtrix), .ply, .obj, .nff (SPD), .json (a scene description,
// scenes/loaders/load_description.h). Throws masq::Error naming the file
// for an unknown extension or bad content.
#pragma once
#include "scenes/loaders/loader.h"
#include <string>
#include <vector>

namespace masq {
Scene load_scene_file(const std::string& path, const LoadOptions& opt = {});
const std::vector<std::string>& scene_file_extensions(); // ".tfx", ".hair", ...
// True for the formats whose files carry their own camera (.nff, .json); the others'
// cameras frame what the file holds. Throws masq::Error for an unknown extension.
bool scene_file_carries_view(const std::string& path);
} // namespace masq
