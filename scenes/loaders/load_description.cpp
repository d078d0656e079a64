// Scene description files: see load_description.h for the format.
#include "scenes/loaders/load_description.h"
#include "scenes/camera.h"
#include "scenes/curve_tools.h"
#include "masq/error.h"
#include "masq/knobs.h"
#include "scenes/generators.h"
#include "scenes/loaders/load_any.h"
#include "scenes/loaders/loader.h"
#include "scenes/strand_generators.h"
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <initializer_list>
#include <limits>
#include <nlohmann/json.hpp>

namespace masq {
namespace {

using json = nlohmann::json;

struct Ctx {
  std::string file;     // the description, for messages
  std::string base_dir; // where relative paths start
};

[[noreturn]] void fail(const Ctx& c, const std::string& path, const std::string& what) {
  throw Error(c.file + ": " + path + ": " + what);
}

std::string join(std::initializer_list<const char*> keys) {
  std::string s;
  for (const char* k : keys) s += (s.empty() ? "" : ", ") + std::string(k);
  return s;
}

void require_object(const Ctx& c, const json& j, const std::string& path) {
  if (!j.is_object()) fail(c, path, "expected an object");
}

// Rejects keys outside `allowed` (typos).
void check_keys(const Ctx& c, const json& j, const std::string& path, std::initializer_list<const char*> allowed) {
  require_object(c, j, path);
  for (auto it = j.begin(); it != j.end(); ++it) {
    bool ok = false;
    for (const char* k : allowed) ok = ok || it.key() == k;
    if (!ok) fail(c, (path.empty() ? "" : path + ".") + it.key(), "unknown key (expected one of " + join(allowed) + ")");
  }
}

std::string sub(const std::string& path, const char* key) { return path.empty() ? std::string(key) : path + "." + key; }

double get_number(const Ctx& c, const json& j, const std::string& path) {
  if (!j.is_number()) fail(c, path, "expected a number");
  double v = j.get<double>();
  if (!std::isfinite(v)) fail(c, path, "expected a finite number");
  return v;
}

double get_positive(const Ctx& c, const json& j, const std::string& path) {
  double v = get_number(c, j, path);
  if (!(v > 0.0)) fail(c, path, "expected a positive number");
  return v;
}

long long get_integer(const Ctx& c, const json& j, const std::string& path, long long min, long long max) {
  bool integral = j.is_number_integer() ||
                  (j.is_number_float() && std::isfinite(j.get<double>()) && std::floor(j.get<double>()) == j.get<double>() &&
                   std::fabs(j.get<double>()) < 9.0e15);
  if (!integral) fail(c, path, "expected an integer");
  long long v;
  if (j.is_number_unsigned()) {
    auto u = j.get<std::uint64_t>();
    if (u > std::uint64_t(max)) fail(c, path, "expected an integer in [" + std::to_string(min) + ", " + std::to_string(max) + "]");
    v = static_cast<long long>(u);
  } else {
    v = j.is_number_integer() ? j.get<long long>() : static_cast<long long>(j.get<double>());
  }
  if (v < min || v > max) fail(c, path, "expected an integer in [" + std::to_string(min) + ", " + std::to_string(max) + "]");
  return v;
}

std::uint64_t get_seed(const Ctx& c, const json& j, const std::string& path) {
  if (j.is_number_unsigned()) return j.get<std::uint64_t>();
  return static_cast<std::uint64_t>(get_integer(c, j, path, 0, std::numeric_limits<long long>::max()));
}

std::string get_string(const Ctx& c, const json& j, const std::string& path) {
  if (!j.is_string()) fail(c, path, "expected a string");
  return j.get<std::string>();
}

glm::dvec3 get_vec3(const Ctx& c, const json& j, const std::string& path) {
  if (!j.is_array() || j.size() != 3) fail(c, path, "expected [x,y,z]");
  glm::dvec3 v;
  for (int i = 0; i < 3; ++i) {
    if (!j[i].is_number()) fail(c, path, "expected [x,y,z]");
    v[i] = get_number(c, j[i], path + "[" + std::to_string(i) + "]");
  }
  return v;
}

PrimType get_prim(const Ctx& c, const json& j, const std::string& path, std::initializer_list<PrimType> allowed) {
  std::string s = get_string(c, j, path);
  auto is_allowed = [&](const PrimTypeRow& r) {
    return std::find(allowed.begin(), allowed.end(), r.value) != allowed.end();
  };
  const PrimTypeRow* row = prim_type_table.find(s);
  if (row && is_allowed(*row)) return row->value;
  fail(c, path, "unknown primitive type '" + s + "' (expected " + prim_type_table.choices(is_allowed) + ")");
}

Affine3 get_transform(const Ctx& c, const json& j, const std::string& path) {
  check_keys(c, j, path, {"translate", "rotate", "scale"});
  glm::dvec3 t(0.0), s(1.0);
  glm::dmat3 r(1.0);
  if (j.contains("translate")) t = get_vec3(c, j["translate"], sub(path, "translate"));
  if (j.contains("scale")) {
    const json& js = j["scale"];
    std::string p = sub(path, "scale");
    if (js.is_number()) {
      s = glm::dvec3(get_number(c, js, p));
    } else if (js.is_array() && js.size() == 3 && js[0].is_number() && js[1].is_number() && js[2].is_number()) {
      s = get_vec3(c, js, p);
    } else {
      fail(c, p, "expected a number or [x,y,z]");
    }
    if (s.x == 0.0 || s.y == 0.0 || s.z == 0.0) fail(c, p, "scale must be nonzero");
  }
  if (j.contains("rotate")) {
    const json& jr = j["rotate"];
    std::string p = sub(path, "rotate");
    check_keys(c, jr, p, {"axis", "deg"});
    if (!jr.contains("axis")) fail(c, sub(p, "axis"), "missing (expected [x,y,z])");
    if (!jr.contains("deg")) fail(c, sub(p, "deg"), "missing (expected a number)");
    glm::dvec3 k = get_vec3(c, jr["axis"], sub(p, "axis"));
    double len = glm::length(k);
    if (!(len > 0.0)) fail(c, sub(p, "axis"), "axis must be nonzero");
    k /= len;
    double a = get_number(c, jr["deg"], sub(p, "deg")) * (3.14159265358979323846 / 180.0);
    double cs = std::cos(a), sn = std::sin(a), oc = 1.0 - cs;
    // Rodrigues; glm matrices are column-major: r[col][row].
    glm::dmat3 m;
    m[0] = {cs + oc * k.x * k.x, oc * k.x * k.y + sn * k.z, oc * k.x * k.z - sn * k.y};
    m[1] = {oc * k.y * k.x - sn * k.z, cs + oc * k.y * k.y, oc * k.y * k.z + sn * k.x};
    m[2] = {oc * k.z * k.x + sn * k.y, oc * k.z * k.y - sn * k.x, cs + oc * k.z * k.z};
    r = m;
  }
  Affine3 out;
  glm::dmat3 sm(1.0);
  sm[0][0] = s.x;
  sm[1][1] = s.y;
  sm[2][2] = s.z;
  out.linear = r * sm;
  out.translation = t;
  return out;
}

std::string resolve_path(const Ctx& c, const std::string& raw, const std::string& path) {
  std::string p = raw;
  const std::string var = "${MASQ_DATA}";
  if (p.rfind(var, 0) == 0) {
    const std::optional<std::string> env = knob_text(Knob::Data);
    if (!env || env->empty())
      fail(c, path, "'" + raw + "' uses ${MASQ_DATA} but the environment variable MASQ_DATA is not set");
    p = *env + p.substr(var.size());
  }
  std::filesystem::path fp(p);
  if (fp.is_relative() && !c.base_dir.empty()) fp = std::filesystem::path(c.base_dir) / fp;
  return fp.string();
}

Scene load_object_file(const Ctx& c, const json& o, const std::string& path) {
  check_keys(c, o, path, {"file", "radius", "prim", "subdiv", "transform"});
  std::string file = resolve_path(c, get_string(c, o["file"], sub(path, "file")), sub(path, "file"));
  LoadOptions opt;
  if (o.contains("radius")) opt.radius = float(get_positive(c, o["radius"], sub(path, "radius")));
  if (o.contains("prim")) opt.strand_type = get_prim(c, o["prim"], sub(path, "prim"), {PrimType::Capsule, PrimType::RoundCone});
  // A description naming another description could name itself: not supported.
  if (std::filesystem::path(file).extension() == ".json")
    fail(c, sub(path, "file"), "a scene description cannot include another (.json)");
  try {
    return load_scene_file(file, opt);
  } catch (const Error& e) {
    fail(c, sub(path, "file"), e.what());
  }
}

Scene load_object_generator(const Ctx& c, const json& o, const std::string& path) {
  std::string gp = sub(path, "generator");
  std::string gen = get_string(c, o["generator"], gp);
  auto has = [&](const char* k) { return o.contains(k); };
  auto at = [&](const char* k) -> const json& { return o[k]; };
  const int kMax = 1 << 30;
  if (gen == "bundle") {
    check_keys(c, o, path, {"generator", "count", "radius", "tilt", "seed", "prim", "subdiv", "transform"});
    BundleParams p;
    if (has("count")) p.count = int(get_integer(c, at("count"), sub(path, "count"), 1, kMax));
    if (has("radius")) p.radius = float(get_positive(c, at("radius"), sub(path, "radius")));
    if (has("tilt")) p.tilt_deg = get_number(c, at("tilt"), sub(path, "tilt"));
    if (has("seed")) p.seed = get_seed(c, at("seed"), sub(path, "seed"));
    if (has("prim"))
      p.prim = get_prim(c, at("prim"), sub(path, "prim"),
                        {PrimType::Capsule, PrimType::RoundCone, PrimType::Curve, PrimType::Sphere});
    Scene s;
    s.name = "bundle";
    s.geometries.push_back(make_bundle(p));
    s.instances.push_back({0, {}});
    return s;
  }
  if (gen == "hair" || gen == "fur") {
    check_keys(c, o, path,
               {"generator", "strands", "points", "length", "radius", "curl", "seed", "prim", "subdiv", "transform"});
    HairParams p;
    p.surface = gen == "fur" ? HairSurface::Body : HairSurface::Head;
    if (has("strands")) p.strands = int(get_integer(c, at("strands"), sub(path, "strands"), 1, kMax));
    if (has("points")) p.points = int(get_integer(c, at("points"), sub(path, "points"), 2, 1 << 20));
    if (has("length")) p.length = get_positive(c, at("length"), sub(path, "length"));
    if (has("radius")) p.radius = get_positive(c, at("radius"), sub(path, "radius"));
    if (has("curl")) {
      p.curl = get_number(c, at("curl"), sub(path, "curl"));
      if (p.curl < 0.0) fail(c, sub(path, "curl"), "expected a number >= 0");
    }
    if (has("seed")) p.seed = get_seed(c, at("seed"), sub(path, "seed"));
    if (has("prim"))
      p.type = get_prim(c, at("prim"), sub(path, "prim"), {PrimType::Capsule, PrimType::RoundCone, PrimType::Curve});
    return make_hair_scene(p);
  }
  if (gen == "streamlines") {
    check_keys(c, o, path, {"generator", "lines", "steps", "radius", "seed", "prim", "subdiv", "transform"});
    StreamlineParams p;
    if (has("lines")) p.lines = int(get_integer(c, at("lines"), sub(path, "lines"), 1, kMax));
    if (has("steps")) p.steps = int(get_integer(c, at("steps"), sub(path, "steps"), 1, kMax));
    if (has("radius")) p.radius = get_positive(c, at("radius"), sub(path, "radius"));
    if (has("seed")) p.seed = get_seed(c, at("seed"), sub(path, "seed"));
    if (has("prim"))
      p.type = get_prim(c, at("prim"), sub(path, "prim"), {PrimType::Capsule, PrimType::RoundCone, PrimType::Curve});
    return make_streamline_scene(p);
  }
  if (gen == "ground") {
    check_keys(c, o, path, {"generator", "height", "size", "subdiv", "transform"});
    double height = 0.0, size = 1.0;
    if (has("height")) height = get_number(c, at("height"), sub(path, "height"));
    if (has("size")) size = get_positive(c, at("size"), sub(path, "size"));
    Scene s;
    s.name = "ground";
    s.geometries.push_back(make_ground_plane(height, size));
    s.instances.push_back({0, {}});
    return s;
  }
  fail(c, gp, "unknown generator '" + gen + "' (expected bundle, hair, fur, streamlines or ground)");
}

void append_object(const Ctx& c, Scene& scene, const json& o, const std::string& path) {
  require_object(c, o, path);
  bool is_file = o.contains("file"), is_gen = o.contains("generator");
  if (is_file == is_gen) fail(c, path, "expected exactly one of 'file' or 'generator'");
  Scene part = is_file ? load_object_file(c, o, path) : load_object_generator(c, o, path);
  if (o.contains("subdiv")) {
    int k = int(get_integer(c, o["subdiv"], sub(path, "subdiv"), 1, 1 << 16));
    part = subdivide_curves(part, k);
  }
  Affine3 t;
  if (o.contains("transform")) t = get_transform(c, o["transform"], sub(path, "transform"));
  const auto base = static_cast<std::uint32_t>(scene.geometries.size());
  for (Geometry& g : part.geometries) scene.geometries.push_back(std::move(g));
  for (const Instance& inst : part.instances) {
    Instance out;
    out.geometry = base + inst.geometry;
    out.object_to_world.linear = t.linear * inst.object_to_world.linear;
    out.object_to_world.translation = t.linear * inst.object_to_world.translation + t.translation;
    scene.instances.push_back(out);
  }
}

Camera parse_camera(const Ctx& c, const json& j) {
  const std::string path = "camera";
  check_keys(c, j, path, {"eye", "target", "up", "fov", "ortho_height"});
  Camera cam;
  if (!j.contains("eye")) fail(c, sub(path, "eye"), "missing (expected [x,y,z])");
  if (!j.contains("target")) fail(c, sub(path, "target"), "missing (expected [x,y,z])");
  cam.eye = get_vec3(c, j["eye"], sub(path, "eye"));
  cam.target = get_vec3(c, j["target"], sub(path, "target"));
  if (cam.eye == cam.target) fail(c, sub(path, "target"), "equals the eye");
  if (j.contains("up")) {
    cam.up = get_vec3(c, j["up"], sub(path, "up"));
    if (cam.up == glm::dvec3(0.0)) fail(c, sub(path, "up"), "must be nonzero");
  }
  if (j.contains("fov")) {
    cam.fov_y_deg = get_number(c, j["fov"], sub(path, "fov"));
    if (!(cam.fov_y_deg > 0.0 && cam.fov_y_deg < 180.0)) fail(c, sub(path, "fov"), "expected degrees in (0, 180)");
  }
  if (j.contains("ortho_height")) {
    cam.ortho_height = get_positive(c, j["ortho_height"], sub(path, "ortho_height"));
    cam.orthographic = true;
  }
  return cam;
}

} // namespace

Scene load_description_text(const std::string& text, const std::string& name, const std::string& base_dir) {
  Ctx c{name, base_dir};
  json root;
  try {
    root = json::parse(text);
  } catch (const json::parse_error& e) {
    throw Error(name + ": JSON syntax error at byte " + std::to_string(e.byte) + ": " + e.what());
  } catch (const json::exception& e) {
    // Found by fuzzing: a number out of double range ("1E319") is out_of_range, not a
    // parse_error, and escaped as a non-masq exception.
    throw Error(name + ": bad JSON: " + e.what());
  }
  if (!root.is_object()) throw Error(name + ": expected a JSON object at the top level");
  check_keys(c, root, "", {"name", "camera", "objects"});
  Scene scene;
  scene.name = root.contains("name") ? get_string(c, root["name"], "name")
                                     : std::filesystem::path(name).stem().string();
  if (!root.contains("objects")) fail(c, "objects", "missing (expected a non-empty array)");
  const json& objs = root["objects"];
  if (!objs.is_array() || objs.empty()) fail(c, "objects", "expected a non-empty array");
  for (std::size_t i = 0; i < objs.size(); ++i) append_object(c, scene, objs[i], "objects[" + std::to_string(i) + "]");
  if (root.contains("camera")) {
    scene.camera = parse_camera(c, root["camera"]);
  } else {
    frame_scene(scene);
  }
  return scene;
}

Scene load_description(const std::string& path) {
  std::vector<std::byte> bytes = read_file_bytes(path);
  std::string text(reinterpret_cast<const char*>(bytes.data()), bytes.size());
  std::string dir = std::filesystem::path(path).parent_path().string();
  return load_description_text(text, path, dir);
}

} // namespace masq
