#include "scenes/loaders/load_ply.h"
#include "masq/error.h"
#include "scenes/prim_table.h"
#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <string_view>

namespace masq {
namespace {

enum class PType { I8, U8, I16, U16, I32, U32, F32, F64 };

std::size_t type_size(PType t) {
  switch (t) {
    case PType::I8: case PType::U8: return 1;
    case PType::I16: case PType::U16: return 2;
    case PType::I32: case PType::U32: case PType::F32: return 4;
    case PType::F64: return 8;
  }
  return 1;
}

bool is_float(PType t) { return t == PType::F32 || t == PType::F64; }

bool parse_type(std::string_view s, PType& t) {
  struct Entry { const char* name; PType t; };
  static const Entry table[] = {
      {"char", PType::I8},    {"int8", PType::I8},     {"uchar", PType::U8},   {"uint8", PType::U8},
      {"short", PType::I16},  {"int16", PType::I16},   {"ushort", PType::U16}, {"uint16", PType::U16},
      {"int", PType::I32},    {"int32", PType::I32},   {"uint", PType::U32},   {"uint32", PType::U32},
      {"float", PType::F32},  {"float32", PType::F32}, {"double", PType::F64}, {"float64", PType::F64}};
  for (const Entry& e : table)
    if (s == e.name) { t = e.t; return true; }
  return false;
}

struct Property {
  std::string name;
  bool is_list = false;
  PType count_type = PType::U8;
  PType type = PType::F32;
};

struct Element {
  std::string name;
  std::uint64_t count = 0;
  std::vector<Property> props;
};


std::vector<std::string_view> split_ws(std::string_view s) {
  std::vector<std::string_view> out;
  std::size_t i = 0;
  while (i < s.size()) {
    while (i < s.size() && is_text_space(s[i])) ++i;
    std::size_t b = i;
    while (i < s.size() && !is_text_space(s[i])) ++i;
    if (i > b) out.push_back(s.substr(b, i - b));
  }
  return out;
}

bool parse_number(std::string_view tok, double& v) {
  if (!tok.empty() && tok[0] == '+') tok.remove_prefix(1);
  if (tok.empty()) return false;
  auto r = std::from_chars(tok.data(), tok.data() + tok.size(), v);
  return r.ec == std::errc() && r.ptr == tok.data() + tok.size();
}

// Integer types must hold integral values within their range.
bool in_range(PType t, double v) {
  if (v != std::floor(v)) return false;
  switch (t) {
    case PType::I8: return v >= -128 && v <= 127;
    case PType::U8: return v >= 0 && v <= 255;
    case PType::I16: return v >= -32768 && v <= 32767;
    case PType::U16: return v >= 0 && v <= 65535;
    case PType::I32: return v >= -2147483648.0 && v <= 2147483647.0;
    case PType::U32: return v >= 0 && v <= 4294967295.0;
    default: return true;
  }
}

template <class T>
T load_as(const unsigned char* b) {
  T v;
  std::memcpy(&v, b, sizeof(T));
  return v;
}

// Values of the body, ASCII or binary, with the location of the last one read.
class DataReader {
 public:
  DataReader(std::span<const std::byte> data, std::size_t start, int format, std::size_t first_line,
             const std::string& source)
      : br_(data, source), text_(reinterpret_cast<const char*>(data.data()), data.size()), pos_(start),
        format_(format), line_(first_line), tok_line_(first_line), val_off_(start), source_(source) {}

  bool ascii() const { return format_ == 0; }
  std::size_t offset() const { return pos_; }
  const ByteReader& bytes() const { return br_; }

  std::string where() const {
    return ascii() ? "line " + std::to_string(tok_line_) : "offset " + std::to_string(val_off_);
  }
  [[noreturn]] void fail(const std::string& msg) const { throw Error(source_ + ": " + where() + ": " + msg); }

  double read(PType t, const std::string& what) {
    if (ascii()) {
      std::string_view tok;
      if (!next_token(tok))
        throw Error(source_ + ": line " + std::to_string(line_) + ": unexpected end of file reading " + what +
                    " (truncated or a bad count)");
      double v;
      if (!parse_number(tok, v)) fail(what + ": '" + std::string(tok) + "' is not a number");
      if (!is_float(t) && !in_range(t, v)) fail(what + ": '" + std::string(tok) + "' is not a valid integer of its type");
      return v;
    }
    unsigned char b[8];
    // At most 8 bytes (a double): said to GCC too, whose -Wstringop-overflow otherwise
    // warns of a write past b below (a false positive of std::reverse's inlining).
    const std::size_t n = std::min(type_size(t), sizeof b);
    val_off_ = pos_;
    br_.read(pos_, b, n, what.c_str());
    pos_ += n;
    if (format_ == 2) // big-endian: swap the bytes in place
      for (std::size_t i = 0; i < n / 2; ++i) std::swap(b[i], b[n - 1 - i]);
    switch (t) {
      case PType::I8: return load_as<std::int8_t>(b);
      case PType::U8: return load_as<std::uint8_t>(b);
      case PType::I16: return load_as<std::int16_t>(b);
      case PType::U16: return load_as<std::uint16_t>(b);
      case PType::I32: return load_as<std::int32_t>(b);
      case PType::U32: return load_as<std::uint32_t>(b);
      case PType::F32: return load_as<float>(b);
      case PType::F64: return load_as<double>(b);
    }
    return 0.0;
  }

 private:
  bool next_token(std::string_view& tok) {
    while (pos_ < text_.size() && is_text_space(text_[pos_])) {
      if (text_[pos_] == '\n') ++line_;
      ++pos_;
    }
    if (pos_ >= text_.size()) return false;
    std::size_t b = pos_;
    while (pos_ < text_.size() && !is_text_space(text_[pos_])) ++pos_;
    tok = text_.substr(b, pos_ - b);
    tok_line_ = line_;
    return true;
  }

  ByteReader br_;
  std::string_view text_;
  std::size_t pos_;
  int format_;  // 0 ascii, 1 binary little endian, 2 binary big endian
  std::size_t line_, tok_line_, val_off_;
  std::string source_;
};

int find_prop(const Element& e, std::string_view name) {
  for (std::size_t i = 0; i < e.props.size(); ++i)
    if (e.props[i].name == name) return static_cast<int>(i);
  return -1;
}

} // namespace

Scene load_ply(const std::string& path, const LoadOptions& opt) {
  std::vector<std::byte> bytes = read_file_bytes(path);
  return load_ply(bytes, path, opt);
}

Scene load_ply(std::span<const std::byte> data, const std::string& name, const LoadOptions& opt) {
  const std::string_view text(reinterpret_cast<const char*>(data.data()), data.size());
  auto header_fail = [&](std::size_t line, const std::string& msg) -> void {
    throw Error(name + ": line " + std::to_string(line) + ": " + msg);
  };

  // ---- header
  std::size_t pos = 0, line_no = 0;
  int format = -1;
  std::vector<Element> elements;
  bool ended = false;
  while (pos < text.size()) {
    std::size_t nl = text.find('\n', pos);
    if (nl == std::string_view::npos) break;  // the header ends with a newline
    std::string_view line = text.substr(pos, nl - pos);
    pos = nl + 1;
    ++line_no;
    if (line_no == 1) {
      if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
      if (line != "ply") header_fail(1, "not a PLY file (the first line must be \"ply\")");
      continue;
    }
    std::vector<std::string_view> t = split_ws(line);
    if (t.empty()) continue;
    if (t[0] == "comment" || t[0] == "obj_info") continue;
    if (t[0] == "end_header") { ended = true; break; }
    if (t[0] == "format") {
      if (t.size() != 3) header_fail(line_no, "expected \"format <ascii|binary_little_endian|binary_big_endian> 1.0\"");
      if (t[1] == "ascii") format = 0;
      else if (t[1] == "binary_little_endian") format = 1;
      else if (t[1] == "binary_big_endian") format = 2;
      else header_fail(line_no, "unknown format '" + std::string(t[1]) + "'");
      if (t[2] != "1.0") header_fail(line_no, "unsupported format version '" + std::string(t[2]) + "'");
    } else if (t[0] == "element") {
      if (t.size() != 3) header_fail(line_no, "expected \"element <name> <count>\"");
      Element e;
      e.name = std::string(t[1]);
      auto r = std::from_chars(t[2].data(), t[2].data() + t[2].size(), e.count);
      if (r.ec != std::errc() || r.ptr != t[2].data() + t[2].size())
        header_fail(line_no, "element " + e.name + ": bad count '" + std::string(t[2]) + "'");
      for (const Element& o : elements)
        if (o.name == e.name) header_fail(line_no, "element " + e.name + " declared twice");
      elements.push_back(std::move(e));
    } else if (t[0] == "property") {
      if (elements.empty()) header_fail(line_no, "property before any element");
      Property p;
      if (t.size() >= 2 && t[1] == "list") {
        if (t.size() != 5) header_fail(line_no, "expected \"property list <count type> <item type> <name>\"");
        p.is_list = true;
        if (!parse_type(t[2], p.count_type)) header_fail(line_no, "unknown type '" + std::string(t[2]) + "'");
        if (is_float(p.count_type)) header_fail(line_no, "list count type must be an integer type");
        if (!parse_type(t[3], p.type)) header_fail(line_no, "unknown type '" + std::string(t[3]) + "'");
        p.name = std::string(t[4]);
      } else {
        if (t.size() != 3) header_fail(line_no, "expected \"property <type> <name>\"");
        if (!parse_type(t[1], p.type)) header_fail(line_no, "unknown type '" + std::string(t[1]) + "'");
        p.name = std::string(t[2]);
      }
      elements.back().props.push_back(std::move(p));
    } else {
      header_fail(line_no, "unknown header keyword '" + std::string(t[0]) + "'");
    }
  }
  if (line_no == 0) {
    if (text.substr(0, 3) != "ply") header_fail(1, "not a PLY file (the first line must be \"ply\")");
    header_fail(1, "truncated header (no end_header)");
  }
  if (!ended) header_fail(line_no + 1, "truncated header (no end_header)");
  if (format < 0) header_fail(line_no, "no format line before end_header");

  // ---- what to extract
  const Element* vert_el = nullptr;
  const Element* face_el = nullptr;
  const Element* edge_el = nullptr;
  for (const Element& e : elements) {
    if (e.name == "vertex") vert_el = &e;
    else if (e.name == "face") face_el = &e;
    else if (e.name == "edge") edge_el = &e;
  }
  const std::uint64_t nverts = vert_el ? vert_el->count : 0;
  int px = -1, py = -1, pz = -1, pr = -1, pface = -1, pe1 = -1, pe2 = -1;
  if (vert_el) {
    px = find_prop(*vert_el, "x"); py = find_prop(*vert_el, "y"); pz = find_prop(*vert_el, "z");
    pr = find_prop(*vert_el, "radius");
    if ((px < 0 || py < 0 || pz < 0) && vert_el->count > 0)
      throw Error(name + ": header: element vertex lacks one of the properties x, y, z");
    for (int i : {px, py, pz, pr})
      if (i >= 0 && vert_el->props[i].is_list)
        throw Error(name + ": header: vertex property " + vert_el->props[i].name + " must not be a list");
  }
  if (face_el) {
    pface = find_prop(*face_el, "vertex_indices");
    if (pface < 0) pface = find_prop(*face_el, "vertex_index");
    if (face_el->count > 0 && (pface < 0 || !face_el->props[pface].is_list))
      throw Error(name + ": header: element face lacks the list property vertex_indices");
  }
  if (edge_el) {
    pe1 = find_prop(*edge_el, "vertex1");
    pe2 = find_prop(*edge_el, "vertex2");
    if (edge_el->count > 0 && (pe1 < 0 || pe2 < 0 || edge_el->props[pe1].is_list || edge_el->props[pe2].is_list))
      throw Error(name + ": header: element edge lacks the scalar properties vertex1, vertex2");
  }
  if (!face_el && !edge_el) throw Error(name + ": no face or edge element: nothing to load");

  // ---- body
  DataReader rd(data, pos, format, line_no + 1, name);
  std::vector<glm::vec3> vertices;
  std::vector<float> radii;
  std::vector<glm::uvec3> triangles;
  std::vector<glm::uvec2> edges;
  std::vector<std::uint32_t> poly;
  std::size_t repaired = 0;

  auto index_of = [&](double v, const char* what) -> std::uint32_t {
    if (!(v >= 0) || v != std::floor(v) || v >= static_cast<double>(nverts))
      rd.fail(std::string(what) + " " + (v == std::floor(v) && std::fabs(v) < 1e18 ? std::to_string(static_cast<long long>(v)) : std::to_string(v)) + " out of range (the file has " + std::to_string(nverts) +
              " vertices)");
    return static_cast<std::uint32_t>(v);
  };

  for (const Element& e : elements) {
    if (e.props.empty() || e.count == 0) continue;
    if (!rd.ascii()) {
      // Smallest possible element (lists empty): check the count before allocating.
      std::size_t min_size = 0;
      for (const Property& p : e.props) min_size += type_size(p.is_list ? p.count_type : p.type);
      rd.bytes().require(rd.offset(), e.count, min_size, ("element " + e.name).c_str());
      if (&e == vert_el) {
        vertices.reserve(e.count);
        if (pr >= 0) radii.reserve(e.count);
      } else if (&e == face_el) {
        triangles.reserve(e.count);
      } else if (&e == edge_el) {
        edges.reserve(e.count);
      }
    }
    const std::string what_el = e.name + " ";
    for (std::uint64_t i = 0; i < e.count; ++i) {
      glm::vec3 v(0.0f);
      float r = 0.0f;
      std::uint32_t e1 = 0, e2 = 0;
      for (std::size_t k = 0; k < e.props.size(); ++k) {
        const Property& p = e.props[k];
        const int ki = static_cast<int>(k);
        if (p.is_list) {
          double n = rd.read(p.count_type, what_el + std::to_string(i) + " " + p.name + " count");
          if (n < 0) rd.fail(what_el + std::to_string(i) + ": negative list count");
          const auto count = static_cast<std::uint64_t>(n);
          if (!rd.ascii()) rd.bytes().require(rd.offset(), count, type_size(p.type), (what_el + p.name).c_str());
          const bool is_face = (&e == face_el && ki == pface);
          if (is_face) {
            if (count < 3) rd.fail("face " + std::to_string(i) + " has " + std::to_string(count) + " vertices (needs at least 3)");
            poly.clear();
          }
          for (std::uint64_t j = 0; j < count; ++j) {
            double x = rd.read(p.type, what_el + std::to_string(i) + " " + p.name);
            if (is_face) poly.push_back(index_of(x, "vertex index"));
          }
          if (is_face)
            for (std::size_t j = 1; j + 1 < poly.size(); ++j) triangles.push_back({poly[0], poly[j], poly[j + 1]});
          continue;
        }
        double x = rd.read(p.type, what_el + std::to_string(i) + " " + p.name);
        if (&e == vert_el) {
          if (ki == px || ki == py || ki == pz || ki == pr) {
            if (!std::isfinite(x) || !std::isfinite(static_cast<float>(x)))
              rd.fail("vertex " + std::to_string(i) + ": " + p.name + " is not finite");
            if (ki == px) v.x = static_cast<float>(x);
            else if (ki == py) v.y = static_cast<float>(x);
            else if (ki == pz) v.z = static_cast<float>(x);
            else {
              if (x < 0) {
                if (opt.warn && repaired < 10)
                  opt.warn(name + ": " + rd.where() + ": vertex " + std::to_string(i) + ": negative radius " +
                           std::to_string(x) + " made positive");
                ++repaired;
                x = -x;
              }
              r = static_cast<float>(x);
            }
          }
        } else if (&e == edge_el) {
          if (ki == pe1) e1 = index_of(x, "edge vertex1");
          else if (ki == pe2) e2 = index_of(x, "edge vertex2");
        }
      }
      if (&e == vert_el) {
        vertices.push_back(v);
        if (pr >= 0) radii.push_back(r);
      } else if (&e == edge_el) {
        edges.push_back({e1, e2});
      }
    }
  }
  if (repaired > 10 && opt.warn)
    opt.warn(name + ": " + std::to_string(repaired) + " negative radii made positive in all");

  // ---- scene
  Scene s;
  s.name = name;
  if (face_el) {
    Geometry g;
    g.type = PrimType::Triangle;
    g.vertices = vertices;
    g.triangles = std::move(triangles);
    s.geometries.push_back(std::move(g));
  }
  if (edge_el) {
    float radius = opt.radius;
    if (radius <= 0.0f && pr < 0) {
      glm::vec3 lo(0.0f), hi(0.0f);
      if (!vertices.empty()) {
        lo = hi = vertices[0];
        for (const glm::vec3& p : vertices) { lo = glm::min(lo, p); hi = glm::max(hi, p); }
      }
      float diag = glm::length(hi - lo);
      radius = diag > 0.0f ? 0.002f * diag : 1e-3f;
    }
    require_strand_type(opt, name);
    Geometry g;
    g.type = opt.strand_type;
    const ScenePrimRow& row = scene_prim_row(g.type);
    for (const glm::uvec2& ed : edges) {
      float ra = pr >= 0 ? radii[ed.x] : radius;
      float rb = pr >= 0 ? radii[ed.y] : radius;
      row.add_segment(g, vertices[ed.x], ra, vertices[ed.y], rb);
    }
    s.geometries.push_back(std::move(g));
  }
  for (std::uint32_t i = 0; i < s.geometries.size(); ++i) s.instances.push_back({i, {}});
  return s;
}

} // namespace masq
