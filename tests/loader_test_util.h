// What the loader tests share: the data folder, bytes of a string, the one-error check
// and a LoadOptions whose warnings are kept, a geometry's segment end points
// (test_loaders_neuro, test_loaders_tracks, test_loaders_tck).
#pragma once
#include "masq/error.h"
#include "scenes/loaders/loader.h"
#include <gtest/gtest.h>
#include <cstring>
#include <initializer_list>
#include <string>
#include <vector>

namespace masq::test {

std::string data_dir() { return MASQ_DATA_DIR; }

std::vector<std::byte> bytes_of(const std::string& s) {
  std::vector<std::byte> b(s.size());
  if (!s.empty()) std::memcpy(b.data(), s.data(), s.size()); // memcpy(nullptr, .., 0) is UB (UBSan)
  return b;
}

// Expects masq::Error whose message contains every fragment.
template <class F>
void expect_error(F&& f, std::initializer_list<const char*> fragments) {
  try {
    f();
    ADD_FAILURE() << "no masq::Error thrown";
  } catch (const Error& e) {
    std::string msg = e.what();
    for (const char* frag : fragments) EXPECT_NE(msg.find(frag), std::string::npos) << "message: " << msg << "\nmissing: " << frag;
  }
}

struct WarnLog {
  std::vector<std::string> lines;
  LoadOptions opts(PrimType t = PrimType::Capsule, float radius = 0.0f) {
    LoadOptions o;
    o.strand_type = t;
    o.radius = radius;
    o.warn = [this](const std::string& s) { lines.push_back(s); };
    return o;
  }
};

// Every segment's end points, in order.
inline std::vector<glm::vec3> segment_points(const Geometry& g) {
  std::vector<glm::vec3> v;
  for (const CapsulePrim& c : g.capsules) { v.push_back(c.a); v.push_back(c.b); }
  for (const RoundConePrim& c : g.round_cones) { v.push_back(c.a); v.push_back(c.b); }
  return v;
}

} // namespace masq::test
