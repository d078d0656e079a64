#include "scenes/loaders/loader.h"
#include "masq/error.h"
#include "scenes/prim_table.h"
#include <cerrno>
#include <cmath>
#include <sstream>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>

namespace masq {

std::vector<std::byte> read_file_bytes(const std::string& path) {
  // A directory, FIFO or device (/dev/zero, a path in a scene description) would be
  // read forever or give a meaningless size: only regular files are scene files.
  std::error_code ec;
  auto st = std::filesystem::status(path, ec);
  if (!ec && std::filesystem::exists(st) && !std::filesystem::is_regular_file(st))
    throw Error(path + ": not a regular file");
  std::ifstream f(path, std::ios::binary | std::ios::ate);
  if (!f) throw Error(path + ": cannot open (" + std::strerror(errno) + ")");
  std::streamoff n = f.tellg();
  if (n < 0) throw Error(path + ": cannot read its size");
  std::vector<std::byte> bytes(static_cast<std::size_t>(n));
  f.seekg(0);
  if (n > 0 && !f.read(reinterpret_cast<char*>(bytes.data()), n)) throw Error(path + ": read failed");
  return bytes;
}

void ByteReader::fail(std::size_t offset, const std::string& what) const {
  throw Error(source_ + ": offset " + std::to_string(offset) + ": " + what);
}

void ByteReader::require(std::size_t offset, std::size_t count, std::size_t elem_size, const char* what) const {
  if (elem_size != 0 && count > std::numeric_limits<std::size_t>::max() / elem_size)
    fail(offset, std::string(what) + ": count " + std::to_string(count) + " overflows");
  std::size_t need = count * elem_size;
  if (offset > data_.size() || need > data_.size() - offset)
    fail(offset, std::string(what) + ": need " + std::to_string(need) + " bytes, the file has " +
                     std::to_string(remaining(offset)) + " left (truncated or a bad count)");
}

void ByteReader::read(std::size_t offset, void* dst, std::size_t n, const char* what) const {
  require(offset, n, 1, what);
  std::memcpy(dst, data_.data() + offset, n);
}

void require_strand_type(const LoadOptions& opt, const std::string& source) {
  if (!scene_prim_row(opt.strand_type).add_segment)
    throw Error(source + ": strands can be " + strand_type_names() + ", not " + prim_type_name(opt.strand_type));
}

bool finite3(const glm::vec3& p) { return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z); }

std::string format_number(double v) {
  std::ostringstream s;
  s.precision(9);
  s << v;
  return s.str();
}

Scene scene_of(Geometry g, const std::string& name) {
  Scene s;
  s.name = name;
  s.geometries.push_back(std::move(g));
  s.instances.push_back({0, {}});
  return s;
}

} // namespace masq
