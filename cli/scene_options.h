// Scene and acceleration options shared by every subcommand (the embedded bundle for
// now, with a choice of strand primitive; the run's kernel mode and curve options).
#pragma once
#include "bvh/build_accel.h"
#include "scenes/generators.h"
#include <CLI/CLI.hpp>
#include <string>

namespace masq::cli {
struct SceneOptions {
  BundleParams bundle;
  std::string prim = "capsule";
  int subdivisions = 1; // curves: pre-subdivision into k pieces
  bool orthographic = false;
  std::string mode = "robust";
  std::string curve_obb = "tight";
  int curve_iters = 24;
};
void add_scene_options(CLI::App& cmd, SceneOptions& opt);
Scene make_scene(const SceneOptions& opt);
AccelOptions accel_options(const SceneOptions& opt);
} // namespace masq::cli
