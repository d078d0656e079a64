#include "bench/heatmap.h"
#include "bvh/twolevel/build_accel.h"
#include "image/heat_color.h"
#include "image/image_writer.h"
#include "scenes/camera.h"
#include "masq/error.h"
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fmt/format.h>

namespace masq {

SuiteImage write_call_heatmaps(SuiteContext& ctx, const Scene& scene, const std::string& file,
                               const std::string& caption, int width, int height) {
  Backend* cpu = ctx.pool.get("cpu");
  if (!cpu) throw Error("heatmap: the cpu backend is unavailable: " + ctx.pool.why("cpu"));
  ctx.say("heatmap " + file);
  std::vector<kernel::Ray> rays = make_camera_rays(scene.camera, width, height);
  AccelOptions accel;
  accel.mode = ctx.config.mode;
  std::vector<std::vector<kernel::RayStats>> stats;
  double mean[2] = {0, 0};
  for (Method m : {Method::Ref, Method::Masq}) {
    cpu->set_scene(build_accel(scene, m, accel));
    std::vector<kernel::Hit> hits(rays.size());
    stats.emplace_back(rays.size());
    cpu->trace(rays, hits, stats.back());
    for (const kernel::RayStats& s : stats.back()) mean[stats.size() - 1] += s.isect_calls;
  }
  // One scale for both halves: the 99th percentile of ref's calls, so a few hot pixels
  // do not wash out the rest.
  std::vector<int> calls;
  for (const kernel::RayStats& s : stats[0]) calls.push_back(s.isect_calls);
  std::nth_element(calls.begin(), calls.begin() + calls.size() * 99 / 100, calls.end());
  const int scale = std::max(1, calls[calls.size() * 99 / 100]);
  const int gap = 8, W = 2 * width + gap;
  std::vector<float> rgb(std::size_t(W) * height * 3, 1.0f);
  for (int half = 0; half < 2; ++half)
    for (int y = 0; y < height; ++y)
      for (int x = 0; x < width; ++x) {
        std::size_t i = std::size_t(y) * width + x;
        // Logarithmic: masq's few calls per pixel stay visible beside ref's hundreds.
        heat_color(heat_position(stats[half][i].isect_calls, scale),
                   &rgb[(std::size_t(y) * W + half * (width + gap) + x) * 3]);
      }
  std::filesystem::create_directories(ctx.config.out_dir);
  write_heatmap((std::filesystem::path(ctx.config.out_dir) / file).string(), W, height, rgb, scale);
  const double n = double(rays.size());
  return {file, fmt::format("{} ({}x{} cpu rays; log scale: black 0, blue-red-yellow, white {}+ calls, colour bar below; mean {:.2f} vs {:.2f} calls per ray)", caption,
                            width, height, scale, mean[0] / n, mean[1] / n)};
}

} // namespace masq
