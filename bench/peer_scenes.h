// The peers suite's scenes (bench/suite_peers.cpp): real hair files as capsules and as
// cubic curves, at their own radius and thick, and the embedded default bundle.
#pragma once
#include "bench/suite.h"
#include "scenes/scene.h"
#include <string>
#include <vector>

namespace masq {

struct PeerScene {
  std::string label;
  std::string file;    // under data_dir; empty: the embedded default bundle
  bool curves = false; // the strands as table1's cubic curves instead of as loaded
  bool thick = false;  // every radius set to kThickRadius x the mean segment length
};

// The thicker variant's radius, in mean segment lengths: hair files' own radii are a few
// percent of a segment or less, so this shows what a thicker strand does to both tracers.
constexpr double kThickRadius = 0.05;

// The scenes: bear fur (TressFX 3, 144,339 segments) and Ratboy's mohawk (TressFX 4,
// 69,068), each as capsules and as cubic curves, at the file's radius and thick, and the
// default bundle. Quick: the bear at its own radius and the bundle.
std::vector<PeerScene> peer_scenes(bool quick);

// Every capsule's and round cone's radius set to kThickRadius x the scene's mean segment
// length; throws masq::Error when the scene has no segments.
void thicken(Scene& scene);

// The mean radius of the scene's round primitives (capsules, round cones, curves).
double mean_radius(const Scene& scene);

// The scene in a row's form: thickened first (`thick`), then its strands made cubic
// curves (`curves`).
Scene shape_peer_scene(Scene scene, bool curves, bool thick);

// A hair file as the rows read it: for curves its strands loaded as round cones (the
// points the curves are chained through), then shaped (throws masq::Error naming the
// file). The profiling probes read files through it too.
Scene load_peer_file(const std::string& path, bool curves, bool thick);

// The scene `ps` names, loaded from cfg.data_dir (throws masq::Error naming the file).
Scene load_peer_scene(const SuiteConfig& cfg, const PeerScene& ps);

} // namespace masq
