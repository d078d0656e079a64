// Scene and acceleration options shared by every subcommand (the embedded bundle for
// now, with a choice of strand primitive; the run's kernel mode and curve options).
#pragma once
#include "bvh/twolevel/build_accel.h"
#include "masq/names.h"
#include "scenes/generators.h"
#include "scenes/strand_generators.h"
#include <CLI/CLI.hpp>
#include <string>
#include <vector>

namespace masq::cli {
// The scenes --scene generates (scenes/generators.h, scenes/strand_generators.h).
enum class EmbeddedScene { Bundle, Hair, Fur, Streamlines };
inline constexpr NameRow<EmbeddedScene> embedded_scene_rows[] = {
    {EmbeddedScene::Bundle, "bundle", "the masquerade paper's"},
    {EmbeddedScene::Hair, "hair", "on a head"},
    {EmbeddedScene::Fur, "fur", "on a body"},
    {EmbeddedScene::Streamlines, "streamlines", "ABC flow"},
};
inline constexpr NameTable embedded_scene_table{"scene", embedded_scene_rows};

struct SceneOptions {
  std::string scene = "bundle"; // a name of embedded_scene_table
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
  // Cubic-curve intersectors (curve_isect_table): bench runs each side by side; the others take one.
  std::vector<std::string> curve_isects{"phantom"};
  int cluster_size = 32;     // cluster, auto
  int cluster_classes = 32;  // cluster, auto
  double cluster_leaf_price = 4.0; // cluster, auto: ClusterOptions::leaf_price
  std::vector<double> prices; // auto: node transform isect (empty: defaults)
  // Binary BVH builders (builder_table, bvh/options.h): bench runs each side by side; the other
  // subcommands take one.
  std::vector<std::string> builders{"sah"};
  double sbvh_budget = 2.0;  // sbvh: at most this many references per primitive
  double sbvh_alpha = 1e-5;  // sbvh: overlap / root area that makes a spatial split worth trying
  // BVH node formats (docs/kernels.md): bench runs each side by side; the others take one.
  std::vector<std::string> nodes{"w4"};
  std::string masq_instance = "compact"; // masquerade entries: compact (32 B) or full (64 B)
  std::string blas_occlusion = "nearest"; // occlusion queries' order over a BLAS node's inner children
  int build_threads = 0; // host build threads: 0 every hardware thread, 1 serial (same structure)
};
void add_scene_options(CLI::App& cmd, SceneOptions& opt);
Scene make_scene(const SceneOptions& opt);
// The acceleration options with the first (or only) builder of opt.builders and the
// first (or only) node format of opt.nodes.
AccelOptions accel_options(const SceneOptions& opt);
// Every builder of opt.builders, parsed (throws masq::Error on an unknown name).
std::vector<Builder> parse_builders(const SceneOptions& opt);
// Every node format of opt.nodes, parsed (throws masq::Error on an unknown or repeated one).
std::vector<NodeFormat> node_formats(const SceneOptions& opt);
// The --curve-isect list (bench runs each; the others take the first); throws on a repeat.
std::vector<CurveIsect> curve_isects(const SceneOptions& opt);
} // namespace masq::cli
