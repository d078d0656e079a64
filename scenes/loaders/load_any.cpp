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

namespace {

// One row per scene file format. view: the file carries its own camera (SPD's "v" block,
// a description's "camera"); the others are framed here, except .tfx and .hair, whose
// loaders frame what they read themselves.
struct FileFormatRow {
  const char* extension;
  Scene (*load)(const std::string& path, const LoadOptions& opt);
  bool framed_here;
  bool view;
};

Scene description(const std::string& path, const LoadOptions&) { return load_description(path); }
Scene tressfx(const std::string& path, const LoadOptions& opt) { return load_tressfx(path, opt); }
Scene hair(const std::string& path, const LoadOptions& opt) { return load_hair(path, opt); }
Scene swc(const std::string& path, const LoadOptions& opt) { return load_swc(path, opt); }
Scene trk(const std::string& path, const LoadOptions& opt) { return load_trk(path, opt); }
Scene tck(const std::string& path, const LoadOptions& opt) { return load_tck(path, opt); }
Scene ply(const std::string& path, const LoadOptions& opt) { return load_ply(path, opt); }
Scene obj(const std::string& path, const LoadOptions& opt) { return load_obj(path, opt); }
Scene nff(const std::string& path, const LoadOptions& opt) { return load_nff(path, opt); }

//  extension, loader, framed here, the file's own view
constexpr FileFormatRow formats[] = {
    {".tfx", tressfx, false, false}, {".hair", hair, false, false}, {".swc", swc, true, false},
    {".trk", trk, true, false},      {".tck", tck, true, false},    {".ply", ply, true, false},
    {".obj", obj, true, false},      {".nff", nff, false, true},    {".json", description, false, true},
};

std::string lowered_extension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return ext;
}

const FileFormatRow& format_of(const std::string& path) {
  const std::string ext = lowered_extension(path);
  for (const FileFormatRow& f : formats)
    if (ext == f.extension) return f;
  std::string known;
  for (const FileFormatRow& f : formats) known += (known.empty() ? "" : ", ") + std::string(f.extension);
  throw Error(path + ": unknown scene file type '" + ext + "' (known: " + known + ")");
}

} // namespace

const std::vector<std::string>& scene_file_extensions() {
  static const std::vector<std::string> e = [] {
    std::vector<std::string> v;
    for (const FileFormatRow& f : formats) v.push_back(f.extension);
    return v;
  }();
  return e;
}

bool scene_file_carries_view(const std::string& path) { return format_of(path).view; }

Scene load_scene_file(const std::string& path, const LoadOptions& opt) {
  const FileFormatRow& f = format_of(path);
  Scene s = f.load(path, opt);
  if (f.framed_here) frame_scene(s);
  return s;
}

} // namespace masq
