// Shared contract of the file loaders (scenes/loaders/load_*.h). Each loader reads a
// path or an in-memory buffer into a Scene of one geometry instanced once.
// Bad input throws masq::Error naming the file and the byte offset or line; repairs
// (e.g. a negative radius made positive) are reported through LoadOptions::warn.
// No allocation is sized from an untrusted count before the count is checked against
// the bytes that are actually there.
#pragma once
#include "scenes/scene.h"
#include <cstddef>
#include <functional>
#include <span>
#include <string>
#include <vector>

namespace masq {

struct LoadOptions {
  // Radius for strands whose file has none (or scale for files with thickness in other
  // units). 0: the loader's documented default.
  float radius = 0.0f;
  // How polylines become primitives: Capsule (constant radius per segment) or RoundCone
  // (radius interpolated between samples, the SWC/streamline primitive).
  PrimType strand_type = PrimType::Capsule;
  // Receives one line per repair; empty: repairs are silent but still made.
  std::function<void(const std::string&)> warn;
};

// The whole file as bytes. Throws masq::Error "<path>: cannot open (<why>)".
std::vector<std::byte> read_file_bytes(const std::string& path);

// Bounds-checked little-endian reads; errors name the source and the byte offset.
class ByteReader {
 public:
  ByteReader(std::span<const std::byte> data, std::string source) : data_(data), source_(std::move(source)) {}
  std::size_t size() const { return data_.size(); }
  std::size_t remaining(std::size_t offset) const { return offset <= data_.size() ? data_.size() - offset : 0; }
  // Copies n bytes at offset into dst; throws "<source>: offset <o>: <what>: need n bytes, file has m".
  void read(std::size_t offset, void* dst, std::size_t n, const char* what) const;
  template <class T>
  T get(std::size_t offset, const char* what) const {
    T v;
    read(offset, &v, sizeof(T), what);
    return v;
  }
  // Throws unless count * elem_size bytes are present at offset (checked without overflow).
  void require(std::size_t offset, std::size_t count, std::size_t elem_size, const char* what) const;
  [[noreturn]] void fail(std::size_t offset, const std::string& what) const;
  const std::string& source() const { return source_; }

 private:
  std::span<const std::byte> data_;
  std::string source_;
};

// Throws "<source>: strands can be capsules or round cones, not <type>" unless
// opt.strand_type is one of the two.
void require_strand_type(const LoadOptions& opt, const std::string& source);
bool finite3(const glm::vec3& p);
std::string format_number(double v); // 9 significant digits, for messages
// The text formats' token separators: C's isspace in the "C" locale, whatever the user's locale.
inline bool is_text_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\f' || c == '\v'; }

// One scene holding `g` once, named after the source.
Scene scene_of(Geometry g, const std::string& name);

} // namespace masq
