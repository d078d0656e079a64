// The profiling probes' command-line words (masq_trace_probe, masq_build_probe): each
// probe is a plain main() for valgrind or perf, so its arguments are positional words.
#pragma once
#include "bench/peer_scenes.h"
#include "bvh/options.h"
#include "scenes/generators.h"
#include <cstdint>
#include <initializer_list>
#include <stdexcept>
#include <string>
#include <utility>

namespace masq::probe {

// The value named by v among opts; an unknown word names what it was for.
template <class T> T pick(const std::string& what, const std::string& v, std::initializer_list<std::pair<const char*, T>> opts) {
  for (const auto& [name, value] : opts)
    if (v == name) return value;
  throw std::invalid_argument(what + " '" + v + "' is not one of the choices (see the usage line)");
}

// capsule|curve|thick|thick-curve: a hair file's segments as capsules or as its strands'
// Catmull-Rom cubics, at the file's radius or thick (every radius kThickRadius x the mean
// segment), as the peers suite's rows (bench/peer_scenes.h).
struct Prims {
  bool curves = false;
  bool thick = false;
};

inline Prims prims(const std::string& arg) {
  return pick<Prims>("primitive", arg,
                     {{"capsule", {false, false}}, {"curve", {true, false}}, {"thick", {false, true}}, {"thick-curve", {true, true}}});
}

// FILE, or "bundle": the embedded default scene (the peers suite's bundle row);
// "bundle-hair" and "bundle-ground": that scene with only its strands or only its ground
// plane, under the same camera (what each part of the bundle row's rays costs). In the
// form p names, as the peers suite's rows read it (load_peer_file, shape_peer_scene).
inline Scene scene(const std::string& arg, Prims p = {}) {
  if (arg != "bundle" && arg != "bundle-hair" && arg != "bundle-ground") return load_peer_file(arg, p.curves, p.thick);
  Scene s = make_default_scene();
  if (arg != "bundle") {
    const std::uint32_t kept = arg == "bundle-hair" ? 0 : 1; // make_default_scene: strands, then the ground
    s.geometries = {s.geometries[kept]};
    s.instances = {{0, s.instances[kept].object_to_world}};
  }
  return shape_peer_scene(std::move(s), p.curves, p.thick);
}

inline Method method(const std::string& arg) {
  return pick<Method>("method", arg, {{"ref", Method::Ref}, {"masq", Method::Masq}, {"cluster", Method::Cluster}, {"auto", Method::Auto}});
}

inline NodeFormat nodes(const std::string& arg) {
  return pick<NodeFormat>("nodes", arg,
                          {{"w4", NodeFormat::W4}, {"w8", NodeFormat::W8}, {"q8", NodeFormat::Q8}, {"o4", NodeFormat::O4}});
}

} // namespace masq::probe
