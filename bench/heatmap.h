// Side-by-side heatmaps of intersector calls per pixel, ref (left) and masq (right), on
// one colour scale, as in the masquerade paper's Fig. 1 and Fig. 4.
#pragma once
#include "bench/suite.h"
#include "scenes/scene.h"
#include <string>

namespace masq {

// Traces the scene's camera rays (width x height) with counters on the cpu backend for
// both methods and writes ctx.config.out_dir/file. The caption gets the scale appended.
SuiteImage write_call_heatmaps(SuiteContext& ctx, const Scene& scene, const std::string& file,
                               const std::string& caption, int width = 320, int height = 320);

} // namespace masq
