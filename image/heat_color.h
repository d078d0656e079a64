// The colour ramp and scale of the intersector-call heatmaps (`masq render`, the bench's
// suites).
#pragma once

namespace masq {
// Heat colour ramp for x in [0, 1]: black -> blue -> red -> yellow -> white.
void heat_color(float x, float* rgb);

// Where `calls` falls on a heatmap whose top colour is `max_calls` calls: logarithmic,
// log2(1 + calls) / log2(1 + max_calls), clamped to [0, 1], so a method's few calls per
// pixel stay visible beside another's hundreds on the same scale.
float heat_position(int calls, int max_calls);
} // namespace masq
