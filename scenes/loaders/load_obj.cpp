#include "scenes/loaders/load_obj.h"
#include "masq/error.h"
#include "scenes/prim_table.h"
#include <tiny_obj_loader.h>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <string_view>

namespace masq {
namespace {

bool is_blank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v'; }

// tinyobjloader reads "nan"/"inf" as 0 without a word, so the `v` lines are checked here
// first: every coordinate must be a finite number that fits a float.
void check_vertex_lines(std::string_view text, const std::string& name) {
  std::size_t pos = 0, line_no = 0, vertex = 0;
  while (pos < text.size()) {
    std::size_t nl = text.find('\n', pos);
    if (nl == std::string_view::npos) nl = text.size();
    std::string_view line = text.substr(pos, nl - pos);
    pos = nl + 1;
    ++line_no;
    std::size_t i = 0;
    while (i < line.size() && is_blank(line[i])) ++i;
    if (i + 1 >= line.size() || line[i] != 'v' || !is_blank(line[i + 1])) continue;
    ++vertex;
    i += 2;
    std::string rest(line.substr(i));
    const char* p = rest.c_str();
    for (int k = 0; k < 3; ++k) {
      char* end = nullptr;
      double x = std::strtod(p, &end);
      if (end == p) break;  // missing or malformed: tinyobjloader's rules apply
      if (!std::isfinite(x) || std::fabs(x) > std::numeric_limits<float>::max())
        throw Error(name + ": line " + std::to_string(line_no) + ": vertex " + std::to_string(vertex) + ": " +
                    "xyz"[k] + " coordinate is not finite (" + std::string(p, static_cast<std::size_t>(end - p)) + ")");
      p = end;
    }
  }
}

// First line of `msg` that contains `what`, or "".
std::string line_with(const std::string& msg, std::string_view what) {
  std::size_t at = msg.find(what);
  if (at == std::string::npos) return {};
  std::size_t b = msg.rfind('\n', at);
  b = b == std::string::npos ? 0 : b + 1;
  std::size_t e = msg.find('\n', at);
  return msg.substr(b, e == std::string::npos ? std::string::npos : e - b);
}

void forward_warnings(const std::string& msg, const std::string& name, const LoadOptions& opt) {
  if (!opt.warn) return;
  std::size_t pos = 0;
  while (pos < msg.size()) {
    std::size_t e = msg.find('\n', pos);
    if (e == std::string::npos) e = msg.size();
    std::string line = msg.substr(pos, e - pos);
    pos = e + 1;
    while (!line.empty() && (line.back() == '\r' || line.back() == ' ')) line.pop_back();
    if (!line.empty()) opt.warn(name + ": " + line);
  }
}

} // namespace

Scene load_obj(const std::string& path, const LoadOptions& opt) {
  std::vector<std::byte> bytes = read_file_bytes(path);
  return load_obj(bytes, path, opt);
}

Scene load_obj(std::span<const std::byte> data, const std::string& name, const LoadOptions& opt) {
  require_strand_type(opt, name);
  const std::string text(reinterpret_cast<const char*>(data.data()), data.size());
  check_vertex_lines(text, name);

  tinyobj::ObjReaderConfig config;
  config.triangulate = true;
  config.vertex_color = false;
  tinyobj::ObjReader reader;
  // Materials are ignored: an empty .mtl text, so a missing file never matters.
  reader.ParseFromString(text, std::string(), config);
  if (!reader.Valid()) {
    std::string err = reader.Error();
    while (!err.empty() && (err.back() == '\n' || err.back() == '\r')) err.pop_back();
    if (err.empty()) err = "tinyobjloader could not parse it";
    throw Error(name + ": " + err);
  }
  const std::string& warning = reader.Warning();
  // tinyobjloader only warns about bad face indices (and drops some of those faces).
  for (std::string_view bad : {"out of bounds", "invalid vertex index"}) {
    std::string l = line_with(warning, bad);
    if (!l.empty()) throw Error(name + ": " + l);
  }
  forward_warnings(warning, name, opt);

  const tinyobj::attrib_t& attrib = reader.GetAttrib();
  const std::size_t nverts = attrib.vertices.size() / 3;
  std::vector<glm::vec3> vertices(nverts);
  for (std::size_t i = 0; i < nverts; ++i) {
    glm::vec3 v(static_cast<float>(attrib.vertices[3 * i]), static_cast<float>(attrib.vertices[3 * i + 1]),
                static_cast<float>(attrib.vertices[3 * i + 2]));
    if (!std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z))
      throw Error(name + ": vertex " + std::to_string(i + 1) + " is not finite");
    vertices[i] = v;
  }
  auto index_of = [&](int idx, const std::string& where) -> std::uint32_t {
    if (idx < 0 || static_cast<std::size_t>(idx) >= nverts)
      throw Error(name + ": " + where + ": vertex index " + std::to_string(idx >= 0 ? idx + 1 : idx) +
                  " out of range (the file has " + std::to_string(nverts) + " vertices)");
    return static_cast<std::uint32_t>(idx);
  };

  std::vector<glm::uvec3> triangles;
  std::vector<glm::uvec2> segments;
  for (const tinyobj::shape_t& sh : reader.GetShapes()) {
    const std::string shape = sh.name.empty() ? std::string("shape") : "shape '" + sh.name + "'";
    std::size_t k = 0;
    for (std::size_t f = 0; f < sh.mesh.num_face_vertices.size(); ++f) {
      const std::size_t n = sh.mesh.num_face_vertices[f];
      if (k + n > sh.mesh.indices.size()) throw Error(name + ": " + shape + ": inconsistent face index list");
      if (n != 3)
        throw Error(name + ": " + shape + ": face " + std::to_string(f + 1) + " has " + std::to_string(n) +
                    " vertices after triangulation");
      const std::string where = shape + " face " + std::to_string(f + 1);
      triangles.push_back({index_of(sh.mesh.indices[k].vertex_index, where),
                           index_of(sh.mesh.indices[k + 1].vertex_index, where),
                           index_of(sh.mesh.indices[k + 2].vertex_index, where)});
      k += n;
    }
    k = 0;
    for (std::size_t l = 0; l < sh.lines.num_line_vertices.size(); ++l) {
      const int n = sh.lines.num_line_vertices[l];
      if (n < 0 || k + static_cast<std::size_t>(n) > sh.lines.indices.size())
        throw Error(name + ": " + shape + ": inconsistent line index list");
      const std::string where = shape + " line " + std::to_string(l + 1);
      if (n < 2 && opt.warn) opt.warn(name + ": " + where + " has fewer than 2 vertices: skipped");
      for (int j = 0; j + 1 < n; ++j)
        segments.push_back({index_of(sh.lines.indices[k + j].vertex_index, where),
                            index_of(sh.lines.indices[k + j + 1].vertex_index, where)});
      if (n == 1) index_of(sh.lines.indices[k].vertex_index, where);
      k += static_cast<std::size_t>(n);
    }
  }
  if (triangles.empty() && segments.empty()) throw Error(name + ": no faces and no lines: nothing to load");

  Scene s;
  s.name = name;
  if (!triangles.empty()) {
    Geometry g;
    g.type = PrimType::Triangle;
    g.vertices = vertices;
    g.triangles = std::move(triangles);
    s.geometries.push_back(std::move(g));
  }
  if (!segments.empty()) {
    float radius = opt.radius;
    if (!(radius > 0.0f)) {
      glm::vec3 lo = vertices[0], hi = vertices[0];
      for (const glm::vec3& p : vertices) { lo = glm::min(lo, p); hi = glm::max(hi, p); }
      const float diag = glm::length(hi - lo);
      radius = diag > 0.0f && std::isfinite(diag) ? 0.002f * diag : 1e-3f;
      if (opt.warn)
        opt.warn(name + ": no strand radius given: using " + std::to_string(radius) +
                 " (0.002 x the bounding-box diagonal)");
    }
    Geometry g;
    g.type = opt.strand_type;
    const ScenePrimRow& row = scene_prim_row(g.type);
    for (const glm::uvec2& sg : segments) row.add_segment(g, vertices[sg.x], radius, vertices[sg.y], radius);
    s.geometries.push_back(std::move(g));
  }
  for (std::uint32_t i = 0; i < s.geometries.size(); ++i) s.instances.push_back({i, {}});
  return s;
}

} // namespace masq
