#include "scenes/loaders/load_tracks.h"
#include "masq/error.h"
#include "scenes/prim_table.h"
#include <algorithm>
#include <array>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <optional>
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

// Byte offsets of the header fields read (TrackVis file format, version 2 layout).
constexpr std::size_t kTrkDim = 6;          // int16[3]
constexpr std::size_t kTrkVoxelSize = 12;   // float[3]
constexpr std::size_t kTrkNScalars = 36;    // int16
constexpr std::size_t kTrkNProperties = 238; // int16
constexpr std::size_t kTrkVoxToRas = 440;   // float[4][4], row-major; version 2
constexpr std::size_t kTrkVoxelOrder = 948; // char[4]
constexpr std::size_t kTrkNCount = 988;     // int32
constexpr std::size_t kTrkVersion = 992;    // int32
constexpr std::size_t kTrkHdrSize = 996;    // int32, always 1000

template <class T>
T byte_swapped(T v) {
  unsigned char b[sizeof(T)];
  std::memcpy(b, &v, sizeof v);
  std::reverse(b, b + sizeof(T));
  std::memcpy(&v, b, sizeof v);
  return v;
}

// Reads numbers in the file's byte order. A .trk has no byte-order field: a writer
// stores its own order, and hdr_size, which must be 1000, is what tells a reader; a
// file whose hdr_size reads 1000 only byte-swapped is in the other order throughout
// (header fields, point counts, coordinates, scalars, properties).
class TrkBytes {
 public:
  explicit TrkBytes(const ByteReader& r) : r_(r) {
    const std::int32_t hdr_size = r.get<std::int32_t>(kTrkHdrSize, "hdr_size");
    if (hdr_size == static_cast<std::int32_t>(kTrkHeader)) swap_ = false;
    else if (byte_swapped(hdr_size) == static_cast<std::int32_t>(kTrkHeader)) swap_ = true;
    else
      r.fail(kTrkHdrSize, "hdr_size is " + std::to_string(hdr_size) + " (" + std::to_string(byte_swapped(hdr_size)) +
                              " byte-swapped), expected 1000");
  }
  template <class T>
  T get(std::size_t off, const char* what) const {
    T v = r_.get<T>(off, what);
    return swap_ ? byte_swapped(v) : v;
  }
  const ByteReader& reader() const { return r_; }

 private:
  const ByteReader& r_;
  bool swap_ = false;
};

struct TrkHeader {
  std::int32_t version = 0;
  std::int16_t n_scalars = 0, n_properties = 0;
  std::int32_t n_count = 0;
  std::int16_t dim[3] = {};
  float voxel_size[3] = {};
  float vox_to_ras[4][4] = {}; // all zero where the file records none (version 1)
  std::string voxel_order;     // the characters before the first NUL, at most 4
};

TrkHeader read_trk_header(const TrkBytes& b) {
  const ByteReader& r = b.reader();
  TrkHeader h;
  h.version = b.get<std::int32_t>(kTrkVersion, "version");
  if (h.version < 1 || h.version > 3) r.fail(kTrkVersion, "unsupported TrackVis version " + std::to_string(h.version));
  h.n_scalars = b.get<std::int16_t>(kTrkNScalars, "n_scalars");
  if (h.n_scalars < 0) r.fail(kTrkNScalars, "negative n_scalars " + std::to_string(h.n_scalars));
  h.n_properties = b.get<std::int16_t>(kTrkNProperties, "n_properties");
  if (h.n_properties < 0) r.fail(kTrkNProperties, "negative n_properties " + std::to_string(h.n_properties));
  h.n_count = b.get<std::int32_t>(kTrkNCount, "n_count");
  if (h.n_count < 0) r.fail(kTrkNCount, "negative n_count " + std::to_string(h.n_count));
  for (int i = 0; i < 3; ++i) {
    h.dim[i] = b.get<std::int16_t>(kTrkDim + 2u * i, "dim");
    h.voxel_size[i] = b.get<float>(kTrkVoxelSize + 4u * i, "voxel_size");
  }
  // Version 1 has no vox_to_ras: those bytes are "reserved" there, whatever they hold.
  if (h.version >= 2)
    for (int row = 0; row < 4; ++row)
      for (int col = 0; col < 4; ++col)
        h.vox_to_ras[row][col] = b.get<float>(kTrkVoxToRas + 4u * (4u * row + col), "vox_to_ras");
  char order[4];
  r.read(kTrkVoxelOrder, order, sizeof order, "voxel_order");
  h.voxel_order.assign(order, static_cast<std::size_t>(std::find(order, order + 4, '\0') - order));
  return h;
}

// Which world (RAS) axis each voxel axis runs along, and in which sense: "LPS" is
// {x, -1}, {y, -1}, {z, +1}.
struct AxisDir {
  int ras = 0;
  int sign = 1;
};
using Orientation = std::array<AxisDir, 3>;

// TrackVis's voxel_order letters (case-insensitive); nullopt unless they are three
// letters naming each world axis once.
std::optional<Orientation> orientation_of_codes(std::string_view codes) {
  if (codes.size() != 3) return std::nullopt;
  Orientation o;
  bool seen[3] = {false, false, false};
  for (int i = 0; i < 3; ++i) {
    const char c = static_cast<char>(std::toupper(static_cast<unsigned char>(codes[static_cast<std::size_t>(i)])));
    const char* letters = "LRPAIS";
    const char* at = std::strchr(letters, c);
    if (c == '\0' || at == nullptr) return std::nullopt;
    const int k = static_cast<int>(at - letters);
    o[static_cast<std::size_t>(i)] = AxisDir{k / 2, k % 2 ? 1 : -1};
    if (seen[k / 2]) return std::nullopt;
    seen[k / 2] = true;
  }
  return o;
}

using Mat3 = std::array<std::array<double, 3>, 3>;

double det3(const Mat3& m) {
  return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
         m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
}

// The transposed inverse (cofactors / determinant) of a nonsingular matrix.
Mat3 inverse_transpose(const Mat3& m) {
  const double d = det3(m);
  Mat3 c;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      const int i1 = (i + 1) % 3, i2 = (i + 2) % 3, j1 = (j + 1) % 3, j2 = (j + 2) % 3;
      c[i][j] = (m[i1][j1] * m[i2][j2] - m[i1][j2] * m[i2][j1]) / d;
    }
  return c;
}

// The axis directions of a voxel-to-world matrix the way the reference readers find
// them (nibabel's io_orientation): scale each column to unit length, take the nearest
// rotation (the polar factor, here by Newton's iteration X <- (X + X^-T) / 2), then give
// each voxel axis in turn the world axis its column leans on most, among those not yet
// taken. nullopt where the matrix is singular (no directions to find).
std::optional<Orientation> orientation_of_matrix(const Mat3& rzs) {
  Mat3 x = rzs;
  for (int col = 0; col < 3; ++col) {
    const double n = std::sqrt(x[0][col] * x[0][col] + x[1][col] * x[1][col] + x[2][col] * x[2][col]);
    if (!(n > 0.0)) return std::nullopt;
    for (int row = 0; row < 3; ++row) x[row][col] /= n;
  }
  if (!(std::fabs(det3(x)) > 1e-6)) return std::nullopt;
  for (int it = 0; it < 100; ++it) {
    const Mat3 t = inverse_transpose(x);
    double change = 0.0;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        const double v = 0.5 * (x[i][j] + t[i][j]);
        change = std::max(change, std::fabs(v - x[i][j]));
        x[i][j] = v;
      }
    if (change < 1e-14) break;
  }
  Orientation o;
  for (int col = 0; col < 3; ++col) {
    int best = 0;
    for (int row = 1; row < 3; ++row)
      if (std::fabs(x[row][col]) > std::fabs(x[best][col])) best = row;
    o[static_cast<std::size_t>(col)] = AxisDir{best, x[best][col] < 0.0 ? -1 : 1};
    for (int c = 0; c < 3; ++c) x[best][c] = 0.0; // taken
  }
  return o;
}

// voxmm -> RAS+ world millimetres, as a 3x4 matrix applied in double precision.
struct TrkToWorld {
  double m[3][4] = {};
  glm::dvec3 apply(const glm::vec3& p) const {
    glm::dvec3 q;
    for (int i = 0; i < 3; ++i) q[i] = m[i][0] * p.x + m[i][1] * p.y + m[i][2] * p.z + m[i][3];
    return q;
  }
};

// The voxmm -> world transform of a .trk, or nullopt where the header has no vox_to_ras.
//
// Why: a .trk stores points in "voxmm" (voxel index times voxel size, origin at the
// corner of voxel 0), while a .tck and every other world-space format store RAS+ mm. A
// version-2 header's vox_to_ras maps voxel centres to RAS+ mm, so the reference readers
// (nibabel.streamlines / dipy) compute
//     world = vox_to_ras * reorient(voxmm / voxel_size - 0.5)
// where the -0.5 moves the origin from the voxel corner to its centre, and reorient
// flips or swaps voxel axes where voxel_order (the order the points were written in;
// empty means TrackVis's default LPS) disagrees with the axis directions of vox_to_ras:
// an axis i that runs the other way becomes dim[i] - 1 - v. This follows that, so a .trk
// and a .tck of the same tracts overlay. Without a vox_to_ras (version 1, or [3][3] = 0)
// there is no world frame to go to: nibabel then assumes the identity, which would place
// the points as if voxel (0,0,0) were at the world origin - a guess, so the points are
// kept in voxmm as stored, with a warning.
std::optional<TrkToWorld> trk_to_world(const TrkHeader& h, const ByteReader& r, const std::string& name,
                                       const LoadOptions& opt) {
  if (h.vox_to_ras[3][3] == 0.0f) {
    if (opt.warn)
      opt.warn(name + ": no vox_to_ras in the header (" +
               (h.version == 1 ? std::string("TrackVis version 1") : std::string("vox_to_ras[3][3] is 0")) +
               "); the points stay in TrackVis voxel-mm space, not RAS+ world mm");
    return std::nullopt;
  }
  for (int row = 0; row < 4; ++row)
    for (int col = 0; col < 4; ++col)
      if (!std::isfinite(h.vox_to_ras[row][col]))
        r.fail(kTrkVoxToRas + 4u * (4u * row + col), "vox_to_ras[" + std::to_string(row) + "][" + std::to_string(col) +
                                                          "] is not finite");
  for (int i = 0; i < 3; ++i)
    if (!(h.voxel_size[i] > 0.0f) || !std::isfinite(h.voxel_size[i]))
      r.fail(kTrkVoxelSize + 4u * i, "voxel_size[" + std::to_string(i) + "] is " + format_number(h.voxel_size[i]) +
                                         "; a positive size is needed to apply vox_to_ras");
  Mat3 rzs;
  for (int row = 0; row < 3; ++row)
    for (int col = 0; col < 3; ++col) rzs[row][col] = h.vox_to_ras[row][col];
  const std::optional<Orientation> affine_axes = orientation_of_matrix(rzs);
  if (!affine_axes) r.fail(kTrkVoxToRas, "vox_to_ras is singular (its voxel axes have no directions)");
  std::string order = h.voxel_order;
  if (order.empty()) {
    order = "LPS";
    if (opt.warn) opt.warn(name + ": offset " + std::to_string(kTrkVoxelOrder) +
               ": voxel_order is empty; assuming LPS (TrackVis's default, as nibabel does)");
  }
  const std::optional<Orientation> file_axes = orientation_of_codes(order);
  if (!file_axes) r.fail(kTrkVoxelOrder, "voxel_order '" + order + "' is not three of L/R, P/A, I/S, one per axis");

  // voxel (file order) -> voxel (vox_to_ras order): row i takes the voxel axis of
  // vox_to_ras that runs along the same world axis as the file's axis i (as nibabel's
  // ornt_transform / inv_ornt_aff), reversed over dim[i] where the senses differ.
  double reorient[3][4] = {};
  for (int i = 0; i < 3; ++i) {
    const AxisDir f = (*file_axes)[static_cast<std::size_t>(i)];
    int j = 0;
    while ((*affine_axes)[static_cast<std::size_t>(j)].ras != f.ras) ++j;
    const bool flip = (*affine_axes)[static_cast<std::size_t>(j)].sign != f.sign;
    if (flip && h.dim[i] <= 0)
      r.fail(kTrkDim + 2u * i, "dim[" + std::to_string(i) + "] is " + std::to_string(h.dim[i]) + ", but voxel_order '" +
                                   order + "' reverses that axis of vox_to_ras, which needs the volume's size");
    reorient[i][j] = flip ? -1.0 : 1.0;
    reorient[i][3] = flip ? h.dim[i] - 1.0 : 0.0;
  }
  // voxmm -> voxel centre: v = voxmm / voxel_size - 0.5.
  double to_voxel[3][4] = {};
  for (int i = 0; i < 3; ++i) {
    to_voxel[i][i] = 1.0 / h.voxel_size[i];
    to_voxel[i][3] = -0.5;
  }
  // world = vox_to_ras * reorient * to_voxel, composed as 3x4 affines.
  auto compose = [](const double a[3][4], const double b[3][4], double out[3][4]) {
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 4; ++j) {
        double s = j == 3 ? a[i][3] : 0.0;
        for (int k = 0; k < 3; ++k) s += a[i][k] * b[k][j];
        out[i][j] = s;
      }
  };
  double v2r[3][4];
  for (int row = 0; row < 3; ++row)
    for (int col = 0; col < 4; ++col) v2r[row][col] = h.vox_to_ras[row][col];
  double step[3][4];
  compose(reorient, to_voxel, step);
  TrkToWorld t;
  compose(v2r, step, t.m);
  return t;
}

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
  const TrkBytes b(r);
  const TrkHeader h = read_trk_header(b);
  const std::int16_t n_scalars = h.n_scalars, n_properties = h.n_properties;
  const std::int32_t n_count = h.n_count;

  StrandBuilder sb(name, opt);
  const std::optional<TrkToWorld> to_world = trk_to_world(h, r, name, opt);
  const std::size_t stride = 4u * (3u + static_cast<std::size_t>(n_scalars));
  std::size_t off = kTrkHeader;
  std::size_t tracks = 0;
  while (n_count == 0 ? off < r.size() : tracks < static_cast<std::size_t>(n_count)) {
    if (off >= r.size())
      r.fail(off, "the file ends after " + std::to_string(tracks) + " of n_count " + std::to_string(n_count) +
                      " streamlines");
    std::int32_t m = b.get<std::int32_t>(off, "streamline point count");
    if (m < 0) r.fail(off, "streamline " + std::to_string(tracks) + " has a negative point count " + std::to_string(m));
    std::size_t body = off + 4;
    r.require(body, static_cast<std::size_t>(m), stride, "streamline points");
    std::size_t props = body + static_cast<std::size_t>(m) * stride;
    r.require(props, static_cast<std::size_t>(n_properties), 4, "streamline properties");
    glm::vec3 prev{};
    for (std::int32_t i = 0; i < m; ++i) {
      std::size_t po = body + static_cast<std::size_t>(i) * stride;
      glm::vec3 p(b.get<float>(po, "point"), b.get<float>(po + 4, "point"), b.get<float>(po + 8, "point"));
      if (!finite3(p))
        r.fail(po, "streamline " + std::to_string(tracks) + " point " + std::to_string(i) + " is not finite");
      if (to_world) {
        p = glm::vec3(to_world->apply(p));
        if (!finite3(p))
          r.fail(po, "streamline " + std::to_string(tracks) + " point " + std::to_string(i) +
                         " is not finite in world space (vox_to_ras overflows it)");
      }
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
  auto space = [](char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\v' || c == '\f'; };
  while (!s.empty() && space(s.front())) s.remove_prefix(1);
  while (!s.empty() && space(s.back())) s.remove_suffix(1);
  return s;
}

bool iequals(std::string_view a, std::string_view b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i)
    if (std::tolower(static_cast<unsigned char>(a[i])) != std::tolower(static_cast<unsigned char>(b[i]))) return false;
  return true;
}

[[noreturn]] void fail_tck_line(const std::string& name, std::size_t line, const std::string& what) {
  throw Error(name + ":" + std::to_string(line) + ": " + what);
}

// One "key: value" entry of the header and the line it is on (0: absent).
struct TckEntry {
  std::string_view value;
  std::size_t line = 0;
};

// The entries this loader uses, gathered the way MRtrix reads a tracks header
// (File::KeyValue::Reader, Tractography::__ReaderBase__::open): text from the first '#'
// on a line is a comment; whitespace around keys and values is dropped; "END" ends the
// header; a line without ':' or with an empty key is skipped (MRtrix logs it and reads
// on, it continues nothing). The keys datatype and file are matched without case and
// the last of each counts (MRtrix assigns them); any other key repeated has its values
// joined with newlines, so a repeated "count" is no longer one number.
struct TckHeader {
  std::size_t end = 0; // offset just past the END line
  TckEntry datatype, file;
  std::vector<TckEntry> counts;
};

TckHeader read_tck_header(std::string_view text, const ByteReader& r, const std::string& name, const LoadOptions& opt) {
  TckHeader h;
  std::size_t pos = 0, line_no = 0;
  bool ended = false;
  auto keep_last = [&](TckEntry& slot, std::string_view key, std::string_view value) {
    if (slot.line != 0 && slot.value != value && opt.warn)
      opt.warn(name + ":" + std::to_string(line_no) + ": '" + std::string(key) + "' given again (earlier on line " +
               std::to_string(slot.line) + "); the last one counts, as in MRtrix");
    slot = TckEntry{value, line_no};
  };
  while (pos < text.size()) {
    std::size_t end = text.find('\n', pos);
    if (end == std::string_view::npos) end = text.size();
    std::string_view raw = text.substr(pos, end - pos);
    pos = std::min(end + 1, text.size());
    ++line_no;
    if (line_no == 1) {
      if (trim(raw) != "mrtrix tracks") r.fail(0, "not an MRtrix .tck file (first line is not \"mrtrix tracks\")");
      continue;
    }
    std::string_view line = trim(raw.substr(0, raw.find('#')));
    if (line == "END") {
      ended = true;
      break;
    }
    if (line.empty()) continue;
    const std::size_t colon = line.find(':');
    const std::string_view key = colon == std::string_view::npos ? std::string_view{} : trim(line.substr(0, colon));
    if (key.empty()) {
      if (opt.warn)
        opt.warn(name + ":" + std::to_string(line_no) + ": header line without 'key: value' ignored (as MRtrix does)");
      continue;
    }
    const std::string_view value = trim(line.substr(colon + 1));
    if (iequals(key, "datatype")) keep_last(h.datatype, key, value);
    else if (iequals(key, "file")) keep_last(h.file, key, value);
    else if (key == "count") h.counts.push_back(TckEntry{value, line_no});
  }
  if (!ended) r.fail(text.size(), "header has no END line (truncated?)");
  h.end = pos;
  return h;
}

TckType parse_tck_datatype(const TckEntry& e, const std::string& name) {
  // MRtrix reads datatype names without regard to case.
  const std::pair<const char*, TckType> types[] = {
      {"Float32LE", TckType::F32LE}, {"Float32BE", TckType::F32BE}, {"Float64LE", TckType::F64LE}, {"Float64BE", TckType::F64BE}};
  for (const auto& [spelling, type] : types)
    if (iequals(e.value, spelling)) return type;
  fail_tck_line(name, e.line, "unsupported datatype '" + std::string(e.value) + "' (Float32LE/BE, Float64LE/BE)");
}

std::size_t parse_tck_data_offset(const TckEntry& e, const std::string& name) {
  const std::string_view v = e.value;
  if (v.size() < 2 || v[0] != '.' || (v[1] != ' ' && v[1] != '\t'))
    fail_tck_line(name, e.line, "only 'file: . <offset>' (data in the same file) is supported");
  const std::string_view num = trim(v.substr(1));
  unsigned long long o = 0;
  auto [p, ec] = std::from_chars(num.data(), num.data() + num.size(), o);
  if (ec != std::errc() || p != num.data() + num.size())
    fail_tck_line(name, e.line, "bad data offset '" + std::string(num) + "'");
  return static_cast<std::size_t>(o);
}

// The header's streamline count, where it is one number; only used to warn when the
// data disagree, so an unusable count is reported and skipped rather than fatal.
std::optional<unsigned long long> tck_count(const TckHeader& h, const std::string& name, const LoadOptions& opt) {
  if (h.counts.empty()) return std::nullopt;
  const TckEntry& e = h.counts.back();
  if (h.counts.size() > 1) {
    if (opt.warn)
      opt.warn(name + ":" + std::to_string(e.line) + ": 'count' given again (first on line " +
               std::to_string(h.counts.front().line) +
               "); MRtrix joins repeated values, which leaves no single count, so it is not checked");
    return std::nullopt;
  }
  unsigned long long c = 0;
  auto [p, ec] = std::from_chars(e.value.data(), e.value.data() + e.value.size(), c);
  if (ec != std::errc() || p != e.value.data() + e.value.size()) {
    if (opt.warn)
      opt.warn(name + ":" + std::to_string(e.line) + ": count '" + std::string(e.value) +
               "' is not a number; not checked");
    return std::nullopt;
  }
  return c;
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
  const TckHeader h = read_tck_header(text, r, name, opt);
  if (h.datatype.line == 0) r.fail(0, "header has no datatype");
  const TckType type = parse_tck_datatype(h.datatype, name);
  if (h.file.line == 0) r.fail(0, "header has no 'file: . <offset>'");
  const std::size_t data_offset = parse_tck_data_offset(h.file, name);
  const std::optional<unsigned long long> count = tck_count(h, name, opt);
  if (data_offset < h.end) r.fail(h.end, "data offset " + std::to_string(data_offset) + " lies inside the header");
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
  if (count && *count != tracks && opt.warn)
    opt.warn(name + ": header count " + std::to_string(*count) + " but the data hold " + std::to_string(tracks) +
             " streamlines");
  return scene_of(sb.take(), name);
}

} // namespace masq
