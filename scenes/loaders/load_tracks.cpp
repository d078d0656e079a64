#include "scenes/loaders/load_tracks.h"
#include "masq/error.h"
#include "scenes/prim_table.h"
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <string_view>
#include <vector>

namespace masq {
namespace {

// Collects polylines into one geometry of capsules or round cones.
class StrandBuilder {
 public:
  StrandBuilder(const std::string& name, const LoadOptions& opt) {
    require_strand_type(opt, name);
    g_.type = opt.strand_type;
    row_ = &scene_prim_row(g_.type);
    radius_ = opt.radius;
    if (!(radius_ > 0.0f)) {
      radius_ = kDefaultTrackRadius;
      if (opt.warn)
        opt.warn(name + ": the file has no radius; using " + std::to_string(kDefaultTrackRadius) +
                 " mm (set LoadOptions::radius)");
    }
  }
  void segment(const glm::vec3& a, const glm::vec3& b) { row_->add_segment(g_, a, radius_, b, radius_); }
  void reserve(std::size_t n) { row_->reserve(g_, n); }
  Geometry take() { return std::move(g_); }

 private:
  Geometry g_;
  const ScenePrimRow* row_ = nullptr;
  float radius_ = kDefaultTrackRadius;
};

// ---------------------------------------------------------------- TrackVis .trk

constexpr std::size_t kTrkHeader = 1000;

} // namespace

Scene load_trk(const std::string& path, const LoadOptions& opt) {
  std::vector<std::byte> bytes = read_file_bytes(path);
  return load_trk(bytes, path, opt);
}

Scene load_trk(std::span<const std::byte> data, const std::string& name, const LoadOptions& opt) {
  ByteReader r(data, name);
  r.require(0, kTrkHeader, 1, "TrackVis header");
  char magic[6];
  r.read(0, magic, 6, "magic");
  if (std::memcmp(magic, "TRACK", 5) != 0) r.fail(0, "not a TrackVis file (magic is not \"TRACK\")");
  std::int32_t hdr_size = r.get<std::int32_t>(996, "hdr_size");
  if (hdr_size != static_cast<std::int32_t>(kTrkHeader)) {
    if (hdr_size == static_cast<std::int32_t>(0xE8030000u))
      r.fail(996, "big-endian TrackVis files are not supported");
    r.fail(996, "hdr_size is " + std::to_string(hdr_size) + ", expected 1000");
  }
  std::int32_t version = r.get<std::int32_t>(992, "version");
  if (version < 1 || version > 3) r.fail(992, "unsupported TrackVis version " + std::to_string(version));
  std::int16_t n_scalars = r.get<std::int16_t>(36, "n_scalars");
  if (n_scalars < 0) r.fail(36, "negative n_scalars " + std::to_string(n_scalars));
  std::int16_t n_properties = r.get<std::int16_t>(238, "n_properties");
  if (n_properties < 0) r.fail(238, "negative n_properties " + std::to_string(n_properties));
  std::int32_t n_count = r.get<std::int32_t>(988, "n_count");
  if (n_count < 0) r.fail(988, "negative n_count " + std::to_string(n_count));

  StrandBuilder sb(name, opt);
  const std::size_t stride = 4u * (3u + static_cast<std::size_t>(n_scalars));
  std::size_t off = kTrkHeader;
  std::size_t tracks = 0;
  std::vector<glm::vec3> pts;
  while (n_count == 0 ? off < r.size() : tracks < static_cast<std::size_t>(n_count)) {
    if (off >= r.size())
      r.fail(off, "the file ends after " + std::to_string(tracks) + " of n_count " + std::to_string(n_count) +
                      " streamlines");
    std::int32_t m = r.get<std::int32_t>(off, "streamline point count");
    if (m < 0) r.fail(off, "streamline " + std::to_string(tracks) + " has a negative point count " + std::to_string(m));
    std::size_t body = off + 4;
    r.require(body, static_cast<std::size_t>(m), stride, "streamline points");
    std::size_t props = body + static_cast<std::size_t>(m) * stride;
    r.require(props, static_cast<std::size_t>(n_properties), 4, "streamline properties");
    glm::vec3 prev{};
    for (std::int32_t i = 0; i < m; ++i) {
      std::size_t po = body + static_cast<std::size_t>(i) * stride;
      float xyz[3];
      r.read(po, xyz, sizeof xyz, "point");
      glm::vec3 p(xyz[0], xyz[1], xyz[2]);
      if (!finite3(p))
        r.fail(po, "streamline " + std::to_string(tracks) + " point " + std::to_string(i) + " is not finite");
      if (i > 0) sb.segment(prev, p);
      prev = p;
    }
    off = props + 4u * static_cast<std::size_t>(n_properties);
    ++tracks;
  }
  if (off < r.size() && opt.warn)
    opt.warn(name + ": offset " + std::to_string(off) + ": " + std::to_string(r.size() - off) +
             " bytes after the n_count streamlines ignored");
  return scene_of(sb.take(), name);
}

// ---------------------------------------------------------------- MRtrix .tck

namespace {

enum class TckType { F32LE, F32BE, F64LE, F64BE };

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r')) s.remove_suffix(1);
  return s;
}

double decode(const std::byte* p, TckType t) {
  const bool big = t == TckType::F32BE || t == TckType::F64BE;
  const std::size_t n = (t == TckType::F32LE || t == TckType::F32BE) ? 4 : 8;
  unsigned char b[8];
  std::memcpy(b, p, n);
  if (big) // the host is little-endian (x86-64, aarch64 as configured here)
    for (std::size_t i = 0; i < n / 2; ++i) std::swap(b[i], b[n - 1 - i]);
  if (n == 4) {
    float f;
    std::memcpy(&f, b, 4);
    return f;
  }
  double d;
  std::memcpy(&d, b, 8);
  return d;
}

} // namespace

Scene load_tck(const std::string& path, const LoadOptions& opt) {
  std::vector<std::byte> bytes = read_file_bytes(path);
  return load_tck(bytes, path, opt);
}

Scene load_tck(std::span<const std::byte> data, const std::string& name, const LoadOptions& opt) {
  ByteReader r(data, name);
  std::string_view text(reinterpret_cast<const char*>(data.data()), data.size());
  auto fail_line = [&](std::size_t line, const std::string& what) -> void {
    throw Error(name + ":" + std::to_string(line) + ": " + what);
  };
  std::size_t pos = 0, line_no = 0;
  bool ended = false, have_type = false, have_file = false;
  TckType type = TckType::F32LE;
  std::size_t data_offset = 0;
  long long count = -1;
  while (pos < text.size()) {
    std::size_t end = text.find('\n', pos);
    if (end == std::string_view::npos) end = text.size();
    std::string_view line = trim(text.substr(pos, end - pos));
    pos = end + 1;
    ++line_no;
    if (line_no == 1) {
      if (line != "mrtrix tracks") r.fail(0, "not an MRtrix .tck file (first line is not \"mrtrix tracks\")");
      continue;
    }
    if (line == "END") {
      ended = true;
      break;
    }
    if (line.empty()) continue;
    std::size_t colon = line.find(':');
    if (colon == std::string_view::npos) fail_line(line_no, "header line without 'key: value'");
    std::string_view key = trim(line.substr(0, colon)), value = trim(line.substr(colon + 1));
    if (key == "datatype") {
      if (value == "Float32LE") type = TckType::F32LE;
      else if (value == "Float32BE") type = TckType::F32BE;
      else if (value == "Float64LE") type = TckType::F64LE;
      else if (value == "Float64BE") type = TckType::F64BE;
      else fail_line(line_no, "unsupported datatype '" + std::string(value) + "' (Float32LE/BE, Float64LE/BE)");
      have_type = true;
    } else if (key == "file") {
      if (value.size() < 2 || value[0] != '.' || (value[1] != ' ' && value[1] != '\t'))
        fail_line(line_no, "only 'file: . <offset>' (data in the same file) is supported");
      std::string_view num = trim(value.substr(1));
      unsigned long long o = 0;
      auto [p, ec] = std::from_chars(num.data(), num.data() + num.size(), o);
      if (ec != std::errc() || p != num.data() + num.size()) fail_line(line_no, "bad data offset '" + std::string(num) + "'");
      data_offset = static_cast<std::size_t>(o);
      have_file = true;
    } else if (key == "count") {
      long long c = 0;
      auto [p, ec] = std::from_chars(value.data(), value.data() + value.size(), c);
      if (ec == std::errc() && p == value.data() + value.size()) count = c;
    }
  }
  if (!ended) r.fail(text.size(), "header has no END line (truncated?)");
  if (!have_type) r.fail(0, "header has no datatype");
  if (!have_file) r.fail(0, "header has no 'file: . <offset>'");
  if (data_offset < pos) r.fail(pos, "data offset " + std::to_string(data_offset) + " lies inside the header");
  if (data_offset > r.size())
    r.fail(data_offset, "data offset " + std::to_string(data_offset) + " is beyond the end of the file (" +
                            std::to_string(r.size()) + " bytes)");

  const std::size_t elem = (type == TckType::F32LE || type == TckType::F32BE) ? 4 : 8;
  const std::size_t stride = 3 * elem;
  StrandBuilder sb(name, opt);
  std::size_t off = data_offset, tracks = 0, in_track = 0;
  bool terminated = false;
  glm::vec3 prev{};
  while (off < r.size()) {
    r.require(off, 1, stride, "point");
    double v[3];
    for (int k = 0; k < 3; ++k) v[k] = decode(data.data() + off + static_cast<std::size_t>(k) * elem, type);
    int nans = std::isnan(v[0]) + std::isnan(v[1]) + std::isnan(v[2]);
    int infs = std::isinf(v[0]) + std::isinf(v[1]) + std::isinf(v[2]);
    if (nans == 3) { // end of streamline
      if (in_track > 0) ++tracks;
      in_track = 0;
    } else if (infs == 3) { // end of data
      terminated = true;
      break;
    } else if (nans != 0 || infs != 0 || std::fabs(v[0]) > 3.0e38 || std::fabs(v[1]) > 3.0e38 || std::fabs(v[2]) > 3.0e38) {
      r.fail(off, "streamline " + std::to_string(tracks) + " point " + std::to_string(in_track) + " is not finite");
    } else {
      glm::vec3 p(static_cast<float>(v[0]), static_cast<float>(v[1]), static_cast<float>(v[2]));
      if (in_track > 0) sb.segment(prev, p);
      prev = p;
      ++in_track;
    }
    off += stride;
  }
  if (in_track > 0) ++tracks; // last streamline without its NaN separator
  if (!terminated && opt.warn)
    opt.warn(name + ": offset " + std::to_string(off) + ": the data end without the Inf terminator (truncated?)");
  if (count >= 0 && static_cast<unsigned long long>(count) != tracks && opt.warn)
    opt.warn(name + ": header count " + std::to_string(count) + " but the data hold " + std::to_string(tracks) +
             " streamlines");
  return scene_of(sb.take(), name);
}

} // namespace masq
