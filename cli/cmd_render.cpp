// masq render: a shaded image and a heatmap of intersector calls per pixel.
#include "bvh/twolevel/build_accel.h"
#include "cli/commands.h"
#include "cli/device_option.h"
#include "cli/scene_options.h"
#include "host/backend.h"
#include "image/heat_color.h"
#include "image/image_writer.h"
#include "scenes/camera.h"
#include "masq/error.h"
#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <memory>

namespace masq::cli {

namespace {

struct RenderOptions {
  SceneOptions scene;
  std::string backend = "cpu";
  std::string device; // --device (cli/device_option.h)
  std::string method = "masq";
  int width = 640, height = 480;
  std::string out = "masq";
  std::string ext = "png";
  // The heatmap's top colour, in intersector calls: one fixed scale by default, so the
  // heatmaps of two methods or runs compare colour for colour.
  int heat_max = 1024;
};

int render(const RenderOptions& o) {
  if (o.scene.builders.size() > 1)
    throw Error("render: --builder takes one builder here (bench runs several side by side)");
  if (o.scene.nodes.size() > 1)
    throw Error("render: --nodes takes one node format here (bench runs several side by side)");
  Scene scene = make_scene(o.scene);
  std::unique_ptr<Backend> be = make_backend(o.backend);
  be->set_scene(build_accel(scene, parse_method(o.method), accel_options(o.scene)));
  std::vector<kernel::Ray> rays = make_camera_rays(scene.camera, o.width, o.height);
  std::vector<kernel::Hit> hits(rays.size());
  std::vector<kernel::RayStats> stats(rays.size());
  be->trace(rays, hits, stats);
  std::vector<float> shaded(rays.size() * 3), heatmap(rays.size() * 3);
  int max_calls = 0;
  for (const kernel::RayStats& s : stats) max_calls = std::max(max_calls, s.isect_calls);
  const glm::vec3 light = glm::normalize(glm::vec3(-0.4f, 0.8f, -0.5f));
  for (std::size_t i = 0; i < rays.size(); ++i) {
    float* px = &shaded[3 * i];
    if (hits[i].prim < 0) {
      px[0] = 0.18f, px[1] = 0.2f, px[2] = 0.25f;
    } else {
      glm::vec3 n(hits[i].normal[0], hits[i].normal[1], hits[i].normal[2]);
      glm::vec3 d(rays[i].dir[0], rays[i].dir[1], rays[i].dir[2]);
      if (glm::dot(n, d) > 0) n = -n; // shade the side facing the camera
      float lambert = 0.15f + 0.85f * std::max(0.0f, glm::dot(n, light));
      glm::vec3 albedo = hits[i].geom == 0 ? glm::vec3(0.85f, 0.6f, 0.3f) : glm::vec3(0.6f, 0.65f, 0.7f);
      for (int k = 0; k < 3; ++k) px[k] = std::pow(albedo[k] * lambert, 1.0f / 2.2f);
    }
    heat_color(heat_position(stats[i].isect_calls, o.heat_max), &heatmap[3 * i]);
  }
  std::string shaded_path = o.out + "_shaded." + o.ext, heat_path = o.out + "_heat." + o.ext;
  write_rgb(shaded_path, o.width, o.height, shaded);
  write_heatmap(heat_path, o.width, o.height, heatmap, o.heat_max);
  fmt::print("{} ({} {}, {}x{}): wrote {} and {} (heatmap: intersector calls per pixel on a log scale, black 0, "
             "white {}+, colour bar below; this image's max {}{})\n",
             scene.name, o.backend, o.method, o.width, o.height, shaded_path, heat_path, o.heat_max, max_calls,
             max_calls > o.heat_max ? ", above the scale: --heat-max" : "");
  return 0;
}

} // namespace

Action add_render(CLI::App& app) {
  auto o = std::make_shared<RenderOptions>();
  CLI::App* cmd = app.add_subcommand("render", "Render a shaded image and an intersector-call heatmap");
  add_scene_options(*cmd, o->scene);
  cmd->add_option("--backend", o->backend, "Backend: " + backend_table.help())
      ->capture_default_str()
      ->check(CLI::IsMember(backend_table.names()));
  add_device_option(*cmd, o->device);
  cmd->add_option("--method", o->method, "Method: " + method_table.help())
      ->capture_default_str()
      ->check(CLI::IsMember(method_table.names()));
  cmd->add_option("--width", o->width, "Image width")->capture_default_str()->check(CLI::Range(1, 16384));
  cmd->add_option("--height", o->height, "Image height")->capture_default_str()->check(CLI::Range(1, 16384));
  cmd->add_option("--out", o->out, "Output prefix: PREFIX_shaded.EXT and PREFIX_heat.EXT")->capture_default_str();
  cmd->add_option("--format", o->ext, "png or exr")->capture_default_str()->check(CLI::IsMember({"png", "exr"}));
  cmd->add_option("--heat-max", o->heat_max,
                  "Heatmap: the intersector calls per pixel the top colour stands for (log scale from 0; the same "
                  "for every method and run, so heatmaps compare colour for colour)")
      ->capture_default_str()
      ->check(CLI::Range(1, 1 << 30));
  cmd->footer("Examples:\n"
              "  masq render                                  default bundle on cpu -> masq_shaded.png, masq_heat.png\n"
              "  masq render --backend vulkan --method ref --out bundle\n"
              "  masq render --backend vulkan --device llvmpipe   on the Vulkan device whose name holds llvmpipe\n"
              "  masq render --method ref --builder sbvh+reinsert\n"
              "  masq render --method ref --out ref && masq render --method masq --out masq   two heatmaps, one scale\n"
              "  masq render --file scene.json --width 1024 --height 768 --format exr");
  return [o] {
    apply_device_option(o->device, std::vector<std::string>{o->backend});
    return render(*o);
  };
}

} // namespace masq::cli
