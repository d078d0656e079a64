// Scene selection shared by every subcommand (the embedded bundle for now).
#pragma once
#include "scenes/generators.h"
#include <CLI/CLI.hpp>

namespace masq::cli {
struct SceneOptions {
  BundleParams bundle;
  bool orthographic = false;
};
void add_scene_options(CLI::App& cmd, SceneOptions& opt);
Scene make_scene(const SceneOptions& opt);
} // namespace masq::cli
