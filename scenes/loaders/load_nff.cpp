#include "scenes/loaders/load_nff.h"
#include "masq/error.h"
#include "scenes/camera.h"
#include <charconv>
#include <cmath>
#include <cstdint>
#include <string_view>

namespace masq {
namespace {


class Tokens {
 public:
  Tokens(std::string_view text, std::string source) : text_(text), source_(std::move(source)) {}

  // Next token anywhere; false at the end of the input.
  bool next(std::string_view& tok) {
    skip_space(true);
    return take(tok);
  }
  // Next token on the current line; false at the end of the line.
  bool next_on_line(std::string_view& tok) {
    skip_space(false);
    if (pos_ < text_.size() && text_[pos_] == '\n') return false;
    return take(tok);
  }
  void skip_line() {
    while (pos_ < text_.size() && text_[pos_] != '\n') ++pos_;
  }
  std::size_t line() const { return tok_line_; }
  [[noreturn]] void fail(std::size_t line, const std::string& msg) const {
    throw Error(source_ + ": line " + std::to_string(line) + ": " + msg);
  }

  // A finite number for `what` (part of the statement that started on line `stmt_line`).
  double number(std::size_t stmt_line, const std::string& what) {
    std::string_view tok;
    if (!next(tok))
      fail(stmt_line, what + ": unexpected end of file (truncated statement)");
    return parse(tok, what);
  }
  double parse(std::string_view tok, const std::string& what) const {
    std::string_view t = tok;
    if (!t.empty() && t[0] == '+') t.remove_prefix(1);
    double v = 0.0;
    auto r = std::from_chars(t.data(), t.data() + t.size(), v);
    if (t.empty() || r.ec != std::errc() || r.ptr != t.data() + t.size())
      fail(tok_line_, what + ": '" + std::string(tok) + "' is not a number");
    if (!std::isfinite(v) || !std::isfinite(static_cast<float>(v)))
      fail(tok_line_, what + ": '" + std::string(tok) + "' is not finite");
    return v;
  }

 private:
  void skip_space(bool newlines) {
    while (pos_ < text_.size() && is_text_space(text_[pos_])) {
      if (text_[pos_] == '\n') {
        if (!newlines) return;
        ++line_;
      }
      ++pos_;
    }
  }
  bool take(std::string_view& tok) {
    if (pos_ >= text_.size()) return false;
    std::size_t b = pos_;
    while (pos_ < text_.size() && !is_text_space(text_[pos_])) ++pos_;
    tok = text_.substr(b, pos_ - b);
    tok_line_ = line_;
    return true;
  }

  std::string_view text_;
  std::string source_;
  std::size_t pos_ = 0, line_ = 1, tok_line_ = 1;
};

} // namespace

Scene load_nff(const std::string& path, const LoadOptions& opt) {
  std::vector<std::byte> bytes = read_file_bytes(path);
  return load_nff(bytes, path, opt);
}

Scene load_nff(std::span<const std::byte> data, const std::string& name, const LoadOptions& opt) {
  Tokens tk(std::string_view(reinterpret_cast<const char*>(data.data()), data.size()), name);
  Geometry spheres, round_cones, tris;
  spheres.type = PrimType::Sphere;
  round_cones.type = PrimType::RoundCone;
  tris.type = PrimType::Triangle;
  Scene s;
  s.name = name;

  auto vec = [&](std::size_t line, const std::string& what) {
    double x = tk.number(line, what + " x");
    double y = tk.number(line, what + " y");
    double z = tk.number(line, what + " z");
    return glm::dvec3(x, y, z);
  };
  auto radius = [&](std::size_t line, const std::string& what) {
    double r = tk.number(line, what);
    if (r < 0) {
      if (opt.warn)
        opt.warn(name + ": line " + std::to_string(tk.line()) + ": negative " + what + " " + std::to_string(r) +
                 " made positive");
      r = -r;
    }
    return static_cast<float>(r);
  };
  auto rest_numbers = [&](const std::string& what) {
    std::string_view tok;
    while (tk.next_on_line(tok)) tk.parse(tok, what);
  };

  std::string_view kw;
  bool viewed = false; // a "v" block's "from" seen: the file's own camera
  while (tk.next(kw)) {
    const std::size_t L = tk.line();
    if (kw[0] == '#') {
      tk.skip_line();
    } else if (kw == "v") {
    } else if (kw == "from") {
      viewed = true;
      s.camera.eye = vec(L, "from");
    } else if (kw == "at") {
      s.camera.target = vec(L, "at");
    } else if (kw == "up") {
      s.camera.up = vec(L, "up");
    } else if (kw == "angle") {
      double a = tk.number(L, "angle");
      if (!(a > 0 && a < 180)) tk.fail(L, "angle " + std::to_string(a) + " is not in (0, 180) degrees");
      s.camera.fov_y_deg = a;
    } else if (kw == "hither") {
      tk.number(L, "hither");
    } else if (kw == "resolution") {
      double w = tk.number(L, "resolution width"), h = tk.number(L, "resolution height");
      if (!(w > 0 && h > 0)) tk.fail(L, "resolution must be positive");
    } else if (kw == "b" || kw == "l" || kw == "f") {
      rest_numbers(std::string(kw) + " value");
    } else if (kw == "s") {
      glm::vec3 c = vec(L, "sphere center");
      float r = radius(L, "sphere radius");
      spheres.spheres.push_back({c, r});
    } else if (kw == "c") {
      glm::vec3 a = vec(L, "cone base");
      float ra = radius(L, "cone base radius");
      glm::vec3 b = vec(L, "cone apex");
      float rb = radius(L, "cone apex radius");
      round_cones.round_cones.push_back({a, ra, b, rb});
    } else if (kw == "p" || kw == "pp") {
      const bool normals = kw == "pp";
      double n = tk.number(L, "polygon vertex count");
      if (n != std::floor(n) || n < 3)
        tk.fail(L, "polygon with " + std::to_string(n) + " vertices (needs an integer >= 3)");
      // Range-check before the cast (found by fuzzing: "p 3.9e29" or "p inf" made the
      // double -> integer conversion undefined).
      if (!(n + double(tris.vertices.size()) <= 4294967295.0)) tk.fail(L, "too many polygon vertices");
      const auto count = static_cast<std::uint64_t>(n);
      const auto first = static_cast<std::uint32_t>(tris.vertices.size());
      for (std::uint64_t i = 0; i < count; ++i) {  // grows as vertices are actually read
        tris.vertices.push_back(glm::vec3(vec(L, "polygon vertex " + std::to_string(i))));
        if (normals) vec(L, "polygon normal " + std::to_string(i));
      }
      for (std::uint32_t i = 1; i + 1 < count; ++i) tris.triangles.push_back({first, first + i, first + i + 1});
    } else {
      tk.fail(L, "unknown keyword '" + std::string(kw) + "'");
    }
  }

  for (Geometry* g : {&spheres, &round_cones, &tris}) {
    if (g->primitive_count() == 0) continue;
    s.instances.push_back({static_cast<std::uint32_t>(s.geometries.size()), {}});
    s.geometries.push_back(std::move(*g));
  }
  if (s.geometries.empty()) throw Error(name + ": no primitives (no s, c or p statements)");
  if (!viewed) frame_scene(s); // SPD files have a view; one without gets a camera that frames it
  return s;
}

} // namespace masq
