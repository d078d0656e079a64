// The colour ramp of the intersector-call heatmaps (`masq render`, the bench's suites).
#pragma once

namespace masq {
// Heat colour ramp for x in [0, 1]: black -> blue -> red -> yellow -> white.
void heat_color(float x, float* rgb);
} // namespace masq
