#include "cli/scene_options.h"

namespace masq::cli {

void add_scene_options(CLI::App& cmd, SceneOptions& opt) {
  cmd.add_option("--count", opt.bundle.count, "Capsules in the default bundle scene")->capture_default_str()->check(CLI::PositiveNumber);
  cmd.add_option("--radius", opt.bundle.radius, "Capsule radius")->capture_default_str()->check(CLI::PositiveNumber);
  cmd.add_option("--tilt", opt.bundle.tilt_deg, "Bundle tilt in degrees (X-Y plane)")->capture_default_str();
  cmd.add_option("--seed", opt.bundle.seed, "Random seed of the bundle")->capture_default_str();
  cmd.add_flag("--ortho", opt.orthographic, "Orthographic view along +z from z=-5 (the paper's setup)");
}

Scene make_scene(const SceneOptions& opt) {
  Scene s = make_default_scene(opt.bundle);
  if (opt.orthographic) {
    s.camera.eye = {0.0, 0.0, -5.0};
    s.camera.target = {0.0, 0.0, 0.0};
    s.camera.orthographic = true;
    s.camera.ortho_height = 1.8;
  }
  return s;
}

} // namespace masq::cli
