// Scene and acceleration options shared by every subcommand (the embedded bundle for
// now, with a choice of strand primitive; the run's kernel mode and curve options).
#pragma once
#include "bvh/build_accel.h"
#include "scenes/generators.h"
#include "scenes/strand_generators.h"
#include <CLI/CLI.hpp>
#include <string>
#include <vector>

namespace masq::cli {
struct SceneOptions {
  std::string scene = "bundle"; // bundle, hair, fur, streamlines
  std::string file;             // a scene file (overrides --scene)
  float file_radius = 0.0f;     // strands without radii in the file (0: the loader's default)
  int strands = 10000;          // hair, fur, streamlines: strand count
  BundleParams bundle;
  std::string prim = "capsule";
  int subdivisions = 1; // curves: pre-subdivision into k pieces
  bool orthographic = false;
  std::string mode = "robust";
  std::string curve_obb = "tight";
  int curve_iters = 24;
  int cluster_size = 32;     // cluster, auto
  int cluster_classes = 32;  // cluster, auto
  std::vector<double> prices; // auto: node transform isect (empty: defaults)
  std::vector<std::string> nodes{"w4"}; // BVH node formats (bench runs each; others take one)
};
void add_scene_options(CLI::App& cmd, SceneOptions& opt);
Scene make_scene(const SceneOptions& opt);
// Throws masq::Error when opt.nodes names more than one format (only bench runs several).
AccelOptions accel_options(const SceneOptions& opt);
std::vector<NodeFormat> node_formats(const SceneOptions& opt); // throws on an unknown or repeated one
} // namespace masq::cli
