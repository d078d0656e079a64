#include "scenes/loaders/load_hair.h"
#include "scenes/camera.h"
#include "masq/error.h"
#include "scenes/prim_table.h"
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <limits>
#include <sstream>

namespace masq {
namespace {

constexpr std::size_t kHeader = 128;
constexpr std::uint32_t kSegments = 1, kPoints = 2, kThickness = 4, kTransparency = 8, kColor = 16;

bool same_bits(float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; }
bool same_bits(const glm::vec3& a, const glm::vec3& b) {
  return same_bits(a.x, b.x) && same_bits(a.y, b.y) && same_bits(a.z, b.z);
}

// Little-endian writes into a presized buffer (masq targets little-endian hosts, like
// the loaders' ByteReader).
struct Writer {
  std::vector<std::byte>& out;
  std::size_t at = 0;
  template <class T>
  void put(const T& v) {
    std::memcpy(out.data() + at, &v, sizeof(T));
    at += sizeof(T);
  }
};

} // namespace

Scene load_hair(const std::string& path, const LoadOptions& opt) {
  std::vector<std::byte> bytes = read_file_bytes(path);
  return load_hair(bytes, path, opt);
}

Scene load_hair(std::span<const std::byte> data, const std::string& name, const LoadOptions& opt) {
  require_strand_type(opt, name);
  ByteReader r(data, name);
  char magic[4];
  r.read(0, magic, 4, ".hair header (magic)");
  if (std::memcmp(magic, "HAIR", 4) != 0) r.fail(0, "bad magic (expected \"HAIR\"; not a .hair file)");
  r.require(0, kHeader, 1, ".hair header");
  const std::uint32_t strands = r.get<std::uint32_t>(4, "strand count");
  const std::uint32_t npoints = r.get<std::uint32_t>(8, "point count");
  const std::uint32_t flags = r.get<std::uint32_t>(12, "flags");
  const std::uint32_t default_segments = r.get<std::uint32_t>(16, "default segments");
  const float default_thickness = r.get<float>(20, "default thickness");

  if (strands == 0) r.fail(4, "strand count is 0 (no hair)");
  if (!(flags & kPoints)) r.fail(12, "flags " + std::to_string(flags) + " have no points array (bit 2)");

  std::size_t off = kHeader;
  const std::size_t seg_off = off;
  if (flags & kSegments) {
    r.require(off, strands, 2, "segments array (u16 per strand)");
    off += std::size_t(strands) * 2;
  }
  const std::size_t pts_off = off;
  r.require(off, npoints, 12, "points array (f32x3 per point)");
  off += std::size_t(npoints) * 12;
  const std::size_t thick_off = off;
  if (flags & kThickness) {
    r.require(off, npoints, 4, "thickness array (f32 per point)");
    off += std::size_t(npoints) * 4;
  }
  if (flags & kTransparency) {
    r.require(off, npoints, 4, "transparency array (f32 per point)");
    off += std::size_t(npoints) * 4;
  }
  if (flags & kColor) r.require(off, npoints, 12, "color array (f32x3 per point)");

  // Points each strand uses; the sum is checked against npoints as it grows (each strand
  // adds at least 1, so the loop ends within npoints + 1 strands when the counts lie).
  std::vector<std::uint16_t> segs;
  if (flags & kSegments) {
    segs.resize(strands);
    r.read(seg_off, segs.data(), segs.size() * 2, "segments array");
  }
  std::uint64_t needed = 0;
  for (std::uint32_t s = 0; s < strands; ++s) {
    needed += std::uint64_t(segs.empty() ? default_segments : segs[s]) + 1;
    if (needed > npoints)
      r.fail(segs.empty() ? 16 : seg_off + std::size_t(s) * 2,
             "strand " + std::to_string(s) + ": the strands need more points than the " +
                 std::to_string(npoints) + " in the file (bad segment count)");
  }
  if (needed < npoints && opt.warn)
    opt.warn(name + ": " + std::to_string(npoints - needed) + " points beyond the " + std::to_string(strands) +
             " strands are ignored");

  std::vector<glm::vec3> pts(needed);
  r.read(pts_off, pts.data(), needed * 12, "points array");
  std::vector<float> rad(needed);
  glm::dvec3 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
  {
    std::size_t i = 0;
    for (std::uint32_t s = 0; s < strands; ++s) {
      const std::uint64_t n = std::uint64_t(segs.empty() ? default_segments : segs[s]) + 1;
      for (std::uint64_t k = 0; k < n; ++k, ++i) {
        if (!finite3(pts[i]))
          r.fail(pts_off + i * 12, "strand " + std::to_string(s) + " point " + std::to_string(k) +
                                       ": non-finite coordinate (" + format_number(pts[i].x) + ", " + format_number(pts[i].y) +
                                       ", " + format_number(pts[i].z) + ")");
        lo = glm::min(lo, glm::dvec3(pts[i]));
        hi = glm::max(hi, glm::dvec3(pts[i]));
      }
    }
  }

  if (flags & kThickness) {
    r.read(thick_off, rad.data(), needed * 4, "thickness array");
    std::size_t i = 0, negative = 0;
    for (std::uint32_t s = 0; s < strands; ++s) {
      const std::uint64_t n = std::uint64_t(segs.empty() ? default_segments : segs[s]) + 1;
      for (std::uint64_t k = 0; k < n; ++k, ++i) {
        float t = rad[i];
        if (!std::isfinite(t))
          r.fail(thick_off + i * 4, "strand " + std::to_string(s) + " point " + std::to_string(k) +
                                        ": thickness is " + format_number(t));
        if (t < 0.0f) {
          if (negative == 0 && opt.warn)
            opt.warn(name + ": offset " + std::to_string(thick_off + i * 4) + ": strand " + std::to_string(s) +
                     " point " + std::to_string(k) + ": negative thickness " + format_number(t) + " made positive");
          ++negative;
          t = -t;
        }
        rad[i] = t * 0.5f;
      }
    }
    if (negative > 1 && opt.warn)
      opt.warn(name + ": " + std::to_string(negative) + " negative thickness values made positive in all");
  } else {
    float t = default_thickness;
    float radius;
    if (std::isfinite(t) && t != 0.0f) {
      if (t < 0.0f) {
        if (opt.warn) opt.warn(name + ": offset 20: negative default thickness " + format_number(t) + " made positive");
        t = -t;
      }
      radius = t * 0.5f;
    } else if (opt.radius > 0.0f) {
      radius = opt.radius;
    } else {
      double diag = glm::length(hi - lo);
      radius = diag > 0.0 ? float(1e-3 * diag) : 1e-3f;
      if (opt.warn)
        opt.warn(name + ": no thickness in the file (default thickness " + format_number(default_thickness) +
                 "); using radius " + format_number(radius) + " (1e-3 x bounding-box diagonal " + format_number(diag) +
                 "); set LoadOptions::radius to choose one");
    }
    std::fill(rad.begin(), rad.end(), radius);
  }

  Geometry g;
  g.type = opt.strand_type;
  const ScenePrimRow& row = scene_prim_row(g.type);
  row.reserve(g, needed - strands); // every strand has >= 1 point
  std::size_t i = 0;
  for (std::uint32_t s = 0; s < strands; ++s) {
    const std::uint64_t n = std::uint64_t(segs.empty() ? default_segments : segs[s]) + 1;
    for (std::uint64_t k = 0; k + 1 < n; ++k) {
      const std::size_t a = i + k, b = a + 1;
      row.add_segment(g, pts[a], rad[a], pts[b], rad[b]);
    }
    i += n;
  }
  Scene sc = scene_of(std::move(g), name);
  frame_scene(sc);
  return sc;
}

std::vector<std::byte> write_hair(const Scene& scene) {
  struct HairStrand { // float points and radii, as the file stores them
    std::vector<glm::vec3> p;
    std::vector<float> r;
  };
  std::vector<HairStrand> strands;
  auto add = [&](const glm::vec3& a, float ra, const glm::vec3& b, float rb) {
    if (!strands.empty()) {
      HairStrand& s = strands.back();
      if (s.p.size() < 65536 && same_bits(s.p.back(), a) && same_bits(s.r.back(), ra)) {
        s.p.push_back(b);
        s.r.push_back(rb);
        return;
      }
    }
    strands.push_back({{a, b}, {ra, rb}});
  };
  auto write_geometry = [&](std::size_t gi) {
    const Geometry& g = scene.geometries[gi];
    const ScenePrimRow& row = scene_prim_row(g.type);
    if (row.shape == PrimShape::Segment) { // the hull of two balls: a capsule or a round cone
      for (std::size_t i = 0; i < row.count(g); ++i) {
        PrimBalls ends;
        row.balls(g, i, ends);
        add(ends[0].centre, ends[0].radius, ends[1].centre, ends[1].radius);
      }
    } else if (g.primitive_count() > 0) {
      throw Error(scene.name + ": write_hair: geometry " + std::to_string(gi) + " holds " +
                  prim_type_name(g.type) + " primitives; .hair stores only capsule or round-cone strands");
    }
  };
  if (scene.instances.empty()) {
    for (std::size_t gi = 0; gi < scene.geometries.size(); ++gi) write_geometry(gi);
  } else {
    for (std::size_t ii = 0; ii < scene.instances.size(); ++ii) {
      const Instance& in = scene.instances[ii];
      if (in.geometry >= scene.geometries.size())
        throw Error(scene.name + ": write_hair: instance " + std::to_string(ii) + " names geometry " +
                    std::to_string(in.geometry) + " of " + std::to_string(scene.geometries.size()));
      if (!in.object_to_world.is_identity())
        throw Error(scene.name + ": write_hair: instance " + std::to_string(ii) +
                    " has a transform; .hair has no instancing (flatten the scene first)");
      write_geometry(in.geometry);
    }
  }
  if (strands.empty()) throw Error(scene.name + ": write_hair: the scene has no capsule or round-cone strands");

  std::uint64_t npoints = 0;
  bool same_segs = true, same_rad = true;
  const std::size_t seg0 = strands[0].p.size() - 1;
  const float r0 = strands[0].r[0];
  for (const HairStrand& s : strands) {
    npoints += s.p.size();
    same_segs = same_segs && s.p.size() - 1 == seg0;
    for (float rr : s.r) same_rad = same_rad && same_bits(rr, r0);
  }
  // The array is omitted only when the default reproduces every radius exactly.
  const float t0 = 2.0f * r0;
  if (!(std::isfinite(t0) && t0 > 0.0f)) same_rad = false;
  if (strands.size() > std::numeric_limits<std::uint32_t>::max() || npoints > std::numeric_limits<std::uint32_t>::max())
    throw Error(scene.name + ": write_hair: too many strands or points for a .hair file");

  const std::size_t total = kHeader + (same_segs ? 0 : strands.size() * 2) + npoints * 12 + (same_rad ? 0 : npoints * 4);
  std::vector<std::byte> out(total);
  Writer w{out};
  const char magic[4] = {'H', 'A', 'I', 'R'};
  w.put(magic);
  w.put(std::uint32_t(strands.size()));
  w.put(std::uint32_t(npoints));
  w.put(std::uint32_t(kPoints | (same_segs ? 0 : kSegments) | (same_rad ? 0 : kThickness)));
  w.put(std::uint32_t(same_segs ? seg0 : 0));
  w.put(same_rad ? t0 : 0.0f);
  w.put(0.0f);                                  // default transparency
  w.put(1.0f), w.put(1.0f), w.put(1.0f);        // default colour
  char info[88] = {};
  std::memcpy(info, "masq write_hair", 15);
  w.put(info);
  if (!same_segs)
    for (const HairStrand& s : strands) w.put(std::uint16_t(s.p.size() - 1));
  for (const HairStrand& s : strands)
    for (const glm::vec3& p : s.p) w.put(p.x), w.put(p.y), w.put(p.z);
  if (!same_rad)
    for (const HairStrand& s : strands)
      for (float rr : s.r) w.put(2.0f * rr);
  return out;
}

void save_hair(const Scene& scene, const std::string& path) {
  std::vector<std::byte> bytes = write_hair(scene);
  std::ofstream f(path, std::ios::binary | std::ios::trunc);
  if (!f) throw Error(path + ": cannot create");
  f.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
  if (!f) throw Error(path + ": write failed");
}

} // namespace masq
