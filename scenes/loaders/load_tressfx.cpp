#include "scenes/loaders/load_tressfx.h"
#include "scenes/camera.h"
#include "masq/error.h"
#include "scenes/prim_table.h"
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <sstream>

namespace masq {
namespace {

constexpr std::size_t kHeaderV3 = 296;
constexpr std::size_t kHeaderV4 = 160;

} // namespace

Scene load_tressfx(const std::string& path, const LoadOptions& opt) {
  std::vector<std::byte> bytes = read_file_bytes(path);
  return load_tressfx(bytes, path, opt);
}

Scene load_tressfx(std::span<const std::byte> data, const std::string& name, const LoadOptions& opt) {
  require_strand_type(opt, name);
  ByteReader r(data, name);
  const float version = r.get<float>(0, "TressFX header (version)");
  int major = 0;
  if (version >= 3.0f && version < 4.0f) major = 3;
  else if (version >= 4.0f && version < 5.0f) major = 4;
  else r.fail(0, "unsupported TressFX version " + format_number(version) + " (expected 3.x or 4.x; not a .tfx file?)");
  const std::size_t header = major == 3 ? kHeaderV3 : kHeaderV4;
  r.require(0, header, 1, major == 3 ? "TressFX 3 header" : "TressFX 4 header");

  const std::uint32_t strands = r.get<std::uint32_t>(4, "numStrands");
  const std::uint32_t vps = r.get<std::uint32_t>(8, "vertsPerStrand");
  const std::size_t pos_field = major == 3 ? 144 : 12;
  const std::size_t thick_field = major == 3 ? 148 : 24;
  const std::uint32_t pos_off = r.get<std::uint32_t>(pos_field, "vertex position offset");
  const std::uint32_t thick_off = r.get<std::uint32_t>(thick_field, "thickness offset");
  const std::size_t stride = major == 3 ? 12 : 16;

  if (strands == 0) r.fail(4, "numStrands is 0 (no hair)");
  if (vps < 2) r.fail(8, "vertsPerStrand is " + std::to_string(vps) + " (a strand needs at least 2 vertices)");
  if (pos_off == 0) r.fail(pos_field, "vertex position offset is 0 (no positions)");
  if (pos_off < header)
    r.fail(pos_field, "vertex position offset " + std::to_string(pos_off) + " points into the " +
                          std::to_string(header) + "-byte header");
  if (pos_off >= r.size())
    r.fail(pos_field, "vertex position offset " + std::to_string(pos_off) + " is outside the file (" +
                          std::to_string(r.size()) + " bytes)");
  const std::size_t nverts = std::size_t(strands) * vps; // < 2^64: both are u32
  r.require(pos_off, nverts, stride, "vertex positions (numStrands x vertsPerStrand)");

  std::vector<float> thickness;
  if (thick_off != 0) {
    if (thick_off < header)
      r.fail(thick_field, "thickness offset " + std::to_string(thick_off) + " points into the header");
    if (thick_off >= r.size())
      r.fail(thick_field, "thickness offset " + std::to_string(thick_off) + " is outside the file (" +
                              std::to_string(r.size()) + " bytes)");
    r.require(thick_off, strands, sizeof(float), "per-strand thickness");
    thickness.resize(strands);
    r.read(thick_off, thickness.data(), std::size_t(strands) * sizeof(float), "per-strand thickness");
    std::size_t negative = 0;
    for (std::uint32_t s = 0; s < strands; ++s) {
      float t = thickness[s];
      if (!std::isfinite(t))
        r.fail(thick_off + std::size_t(s) * 4, "strand " + std::to_string(s) + ": thickness is " + format_number(t));
      if (t < 0.0f) {
        if (negative == 0 && opt.warn)
          opt.warn(name + ": offset " + std::to_string(thick_off + std::size_t(s) * 4) + ": strand " +
                   std::to_string(s) + ": negative thickness " + format_number(t) + " made positive");
        ++negative;
        thickness[s] = -t;
      }
    }
    if (negative > 1 && opt.warn)
      opt.warn(name + ": " + std::to_string(negative) + " negative thickness values made positive in all");
  }

  std::vector<glm::vec3> pts(nverts);
  glm::dvec3 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
  for (std::size_t i = 0; i < nverts; ++i) {
    const std::size_t off = pos_off + i * stride;
    float xyz[3];
    r.read(off, xyz, sizeof xyz, "vertex position");
    glm::vec3 p(xyz[0], xyz[1], xyz[2]);
    if (!finite3(p))
      r.fail(off, "strand " + std::to_string(i / vps) + " vertex " + std::to_string(i % vps) +
                      ": non-finite coordinate (" + format_number(p.x) + ", " + format_number(p.y) + ", " + format_number(p.z) + ")");
    pts[i] = p;
    lo = glm::min(lo, glm::dvec3(p));
    hi = glm::max(hi, glm::dvec3(p));
  }

  float base = opt.radius;
  if (!(base > 0.0f)) {
    double diag = glm::length(hi - lo);
    base = diag > 0.0 ? float(1e-3 * diag) : 1e-3f;
    if (opt.warn)
      opt.warn(name + ": TressFX has no absolute hair width; using radius " + format_number(base) +
               " (1e-3 x bounding-box diagonal " + format_number(diag) + "); set LoadOptions::radius to choose one");
  }

  Geometry g;
  g.type = opt.strand_type;
  const ScenePrimRow& row = scene_prim_row(g.type);
  row.reserve(g, std::size_t(strands) * (vps - 1));
  for (std::uint32_t s = 0; s < strands; ++s) {
    const float rad = thickness.empty() ? base : thickness[s] * base;
    if (!std::isfinite(rad))
      r.fail(thick_off + std::size_t(s) * 4, "strand " + std::to_string(s) + ": thickness " + format_number(thickness[s]) +
                                                 " x radius " + format_number(base) + " overflows");
    const glm::vec3* p = pts.data() + std::size_t(s) * vps;
    for (std::uint32_t v = 0; v + 1 < vps; ++v) {
      row.add_segment(g, p[v], rad, p[v + 1], rad);
    }
  }
  Scene sc = scene_of(std::move(g), name);
  frame_scene(sc);
  return sc;
}

} // namespace masq
