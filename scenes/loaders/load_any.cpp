#include "scenes/loaders/load_any.h"
#include "scenes/camera.h"
#include "masq/error.h"
#include "scenes/loaders/load_description.h"
#include "scenes/loaders/load_hair.h"
#include "scenes/loaders/load_obj.h"
#include "scenes/loaders/load_nff.h"
#include "scenes/loaders/load_ply.h"
#include "scenes/loaders/load_swc.h"
#include "scenes/loaders/load_tracks.h"
#include "scenes/loaders/load_tressfx.h"
#include <algorithm>
#include <cctype>
#include <filesystem>

namespace masq {

const std::vector<std::string>& scene_file_extensions() {
  static const std::vector<std::string> e = {".tfx", ".hair", ".swc", ".trk", ".tck", ".ply", ".obj", ".nff", ".json"};
  return e;
}

Scene load_scene_file(const std::string& path, const LoadOptions& opt) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  if (ext == ".tfx") return load_tressfx(path, opt);
  if (ext == ".hair") return load_hair(path, opt);
  // These formats carry no view: frame what they hold.
  auto framed = [](Scene s) {
    frame_scene(s);
    return s;
  };
  if (ext == ".swc") return framed(load_swc(path, opt));
  if (ext == ".trk") return framed(load_trk(path, opt));
  if (ext == ".tck") return framed(load_tck(path, opt));
  if (ext == ".ply") return framed(load_ply(path, opt));
  if (ext == ".obj") return framed(load_obj(path, opt));
  if (ext == ".json") return load_description(path);
  if (ext == ".nff") return load_nff(path, opt);
  std::string known;
  for (const std::string& e : scene_file_extensions()) known += (known.empty() ? "" : ", ") + e;
  throw Error(path + ": unknown scene file type '" + ext + "' (known: " + known + ")");
}

} // namespace masq
