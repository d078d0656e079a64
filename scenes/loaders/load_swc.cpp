#include "scenes/loaders/load_swc.h"
#include "masq/error.h"
#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <string_view>
#include <unordered_map>
#include <vector>

namespace masq {
namespace {

struct Sample {
  long long id;
  long long parent;
  glm::vec3 pos;
  float radius;
  std::size_t line;
};

bool is_line_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }

[[noreturn]] void fail_line(const std::string& name, std::size_t line, const std::string& what) {
  throw Error(name + ":" + std::to_string(line) + ": " + what);
}

long long parse_int(std::string_view tok, const std::string& name, std::size_t line, const char* what) {
  long long v = 0;
  auto [p, ec] = std::from_chars(tok.data(), tok.data() + tok.size(), v);
  if (ec == std::errc() && p == tok.data() + tok.size()) return v;
  // Some writers print integer columns as "12.0": accept an integral floating value.
  double d = 0.0;
  auto [p2, ec2] = std::from_chars(tok.data(), tok.data() + tok.size(), d);
  if (ec2 == std::errc() && p2 == tok.data() + tok.size() && std::isfinite(d) && d == std::floor(d) &&
      std::fabs(d) < 9.0e15)
    return static_cast<long long>(d);
  fail_line(name, line, std::string(what) + " '" + std::string(tok) + "' is not an integer");
}

double parse_real(std::string_view tok, const std::string& name, std::size_t line, const char* what) {
  double v = 0.0;
  if (!tok.empty() && tok.front() == '+') tok.remove_prefix(1);
  auto [p, ec] = std::from_chars(tok.data(), tok.data() + tok.size(), v);
  if ((ec != std::errc() && ec != std::errc::result_out_of_range) || p != tok.data() + tok.size())
    fail_line(name, line, std::string(what) + " '" + std::string(tok) + "' is not a number");
  if (ec == std::errc::result_out_of_range || !std::isfinite(v) || std::fabs(v) > 3.0e38)
    fail_line(name, line, std::string(what) + " '" + std::string(tok) + "' is not finite");
  return v;
}

// Parent links must lead every sample to a root (parent -1). A loop of links has no
// root: it is a malformed tree (a hand edit, a bad merge of files), and its segments
// would be drawn without anything saying so. Walks each sample's parent chain once
// (samples already known to reach a root are not walked again) and throws naming the
// samples of the first loop and their lines. Parents are known to exist.
void reject_parent_loops(const std::vector<Sample>& samples, const std::unordered_map<long long, std::size_t>& index,
                         const std::string& name) {
  enum : std::uint8_t { Unvisited, OnPath, ReachesRoot };
  std::vector<std::uint8_t> state(samples.size(), Unvisited);
  std::vector<std::size_t> path;
  for (std::size_t start = 0; start < samples.size(); ++start) {
    path.clear();
    std::size_t cur = start;
    bool looped = false;
    while (state[cur] == Unvisited) {
      state[cur] = OnPath;
      path.push_back(cur);
      if (samples[cur].parent < 0) break;
      cur = index.at(samples[cur].parent);
      looped = state[cur] == OnPath;
    }
    if (looped) {
      std::size_t first = 0;
      while (path[first] != cur) ++first;
      const std::size_t length = path.size() - first;
      std::string ids, lines;
      const std::size_t shown = std::min<std::size_t>(length, 8);
      for (std::size_t k = 0; k < shown; ++k) {
        const Sample& s = samples[path[first + k]];
        ids += std::to_string(s.id) + " -> ";
        lines += (k ? ", " : "") + std::to_string(s.line);
      }
      ids += shown < length ? "... (" + std::to_string(length) + " samples) -> " : "";
      ids += std::to_string(samples[cur].id);
      fail_line(name, samples[cur].line,
                "parent links form a loop with no root: sample " + ids + " (lines " + lines +
                    (shown < length ? ", ..." : "") + "); every chain of parents must end at a root (parent -1)");
    }
    for (std::size_t k : path) state[k] = ReachesRoot;
  }
}

} // namespace

Scene load_swc(const std::string& path, const LoadOptions& opt) {
  std::vector<std::byte> bytes = read_file_bytes(path);
  return load_swc(bytes, path, opt);
}

Scene load_swc(std::span<const std::byte> data, const std::string& name, const LoadOptions& opt) {
  std::string_view text(reinterpret_cast<const char*>(data.data()), data.size());
  std::vector<Sample> samples;
  std::unordered_map<long long, std::size_t> index; // id -> sample
  std::size_t negative = 0, first_negative_line = 0;
  const float scale = opt.radius > 0.0f ? opt.radius : 1.0f;

  std::size_t line_no = 0, pos = 0;
  while (pos < text.size()) {
    std::size_t end = text.find('\n', pos);
    if (end == std::string_view::npos) end = text.size();
    std::string_view line = text.substr(pos, end - pos);
    pos = end + 1;
    ++line_no;
    if (std::size_t hash = line.find('#'); hash != std::string_view::npos) line = line.substr(0, hash);
    std::string_view tok[7];
    std::size_t n = 0, i = 0;
    while (i < line.size() && n < 7) {
      while (i < line.size() && is_line_space(line[i])) ++i;
      if (i == line.size()) break;
      std::size_t s = i;
      while (i < line.size() && !is_line_space(line[i])) ++i;
      tok[n++] = line.substr(s, i - s);
    }
    if (n == 0) continue; // blank or comment
    if (line.find('\0') != std::string_view::npos) fail_line(name, line_no, "NUL byte (not a text SWC file?)");
    if (n < 7)
      fail_line(name, line_no,
                "expected 7 fields 'id type x y z radius parent', found " + std::to_string(n));
    Sample s;
    s.line = line_no;
    s.id = parse_int(tok[0], name, line_no, "id");
    (void)parse_int(tok[1], name, line_no, "type");
    s.pos = glm::vec3(static_cast<float>(parse_real(tok[2], name, line_no, "x")),
                      static_cast<float>(parse_real(tok[3], name, line_no, "y")),
                      static_cast<float>(parse_real(tok[4], name, line_no, "z")));
    double r = parse_real(tok[5], name, line_no, "radius");
    s.parent = parse_int(tok[6], name, line_no, "parent");
    if (r < 0.0) {
      if (negative++ == 0) first_negative_line = line_no;
      r = -r;
    }
    s.radius = static_cast<float>(r) * scale;
    if (s.parent >= 0 && s.parent == s.id) fail_line(name, line_no, "sample " + std::to_string(s.id) + " is its own parent");
    auto [it, inserted] = index.emplace(s.id, samples.size());
    if (!inserted)
      fail_line(name, line_no,
                "duplicate id " + std::to_string(s.id) + " (first on line " + std::to_string(samples[it->second].line) + ")");
    samples.push_back(s);
  }

  if (negative > 0 && opt.warn)
    opt.warn(name + ": " + std::to_string(negative) + " sample(s) with a negative radius made positive (first on line " +
             std::to_string(first_negative_line) + ")");

  Geometry g;
  g.type = PrimType::RoundCone;
  std::size_t roots = 0;
  for (const Sample& s : samples) {
    if (s.parent < 0) {
      ++roots;
      continue;
    }
    auto it = index.find(s.parent);
    if (it == index.end())
      fail_line(name, s.line, "sample " + std::to_string(s.id) + " has parent " + std::to_string(s.parent) + ", which does not exist");
    const Sample& p = samples[it->second];
    g.round_cones.push_back(RoundConePrim{p.pos, p.radius, s.pos, s.radius});
  }
  reject_parent_loops(samples, index, name);
  if (g.round_cones.empty())
    throw Error(name + ": no segments (" + std::to_string(samples.size()) + " sample(s), " + std::to_string(roots) +
                " root(s); an SWC file needs samples with parents)");
  return scene_of(std::move(g), name);
}

} // namespace masq
