// A .tck writer for the loader tests (test_loaders_tck, test_loaders_tracks): the bytes
// MRtrix writes, in any of its datatypes.
#pragma once
#include "tests/loader_test_util.h"
#include <glm/glm.hpp>
#include <cstddef>
#include <cstring>
#include <limits>
#include <string>
#include <utility>
#include <vector>

namespace masq::test {

template <class T>
void append_value(std::vector<std::byte>& b, T v, bool big) {
  unsigned char raw[sizeof(T)];
  std::memcpy(raw, &v, sizeof v);
  if (big)
    for (std::size_t i = 0; i < sizeof(T) / 2; ++i) std::swap(raw[i], raw[sizeof(T) - 1 - i]);
  for (unsigned char c : raw) b.push_back(static_cast<std::byte>(c));
}

// Writes a .tck the way MRtrix does: header, padding to the data offset, xyz triplets,
// a NaN triplet after each streamline, an Inf triplet at the end.
inline std::vector<std::byte> write_tck(const std::vector<std::vector<glm::vec3>>& tracks, const std::string& datatype = "Float32LE",
                                 bool terminate = true, std::size_t offset = 0) {
  std::string head = "mrtrix tracks\ntimestamp: 1.0\ndatatype: " + datatype + "\ncount: " + std::to_string(tracks.size()) + "\n";
  const std::size_t off = offset ? offset : head.size() + std::string("file: . 1000\nEND\n").size() + 3;
  head += "file: . " + std::to_string(off) + "\nEND\n";
  std::vector<std::byte> b = bytes_of(head);
  b.resize(off, std::byte{0});
  const bool big = datatype.ends_with("BE");
  const bool f64 = datatype.starts_with("Float64");
  auto put = [&](double x, double y, double z) {
    for (double v : {x, y, z}) {
      if (f64) append_value<double>(b, v, big);
      else append_value<float>(b, static_cast<float>(v), big);
    }
  };
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  for (const auto& t : tracks) {
    for (const glm::vec3& p : t) put(p.x, p.y, p.z);
    put(nan, nan, nan);
  }
  if (terminate) put(inf, inf, inf);
  return b;
}

} // namespace masq::test
