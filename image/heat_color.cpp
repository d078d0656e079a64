// heat_color: three overlapping linear ramps, clamped.
#include "image/heat_color.h"
#include <algorithm>
#include <cmath>

namespace masq {

void heat_color(float x, float* rgb) {
  x = std::clamp(x, 0.0f, 1.0f);
  rgb[0] = std::clamp(3.0f * x - 1.0f, 0.0f, 1.0f);
  rgb[1] = std::clamp(3.0f * x - 2.0f, 0.0f, 1.0f);
  rgb[2] = std::clamp(x < 0.33f ? 3.0f * x : 2.0f - 3.0f * x, 0.0f, 1.0f) + std::clamp(3.0f * x - 2.0f, 0.0f, 1.0f);
}

} // namespace masq

namespace masq {

float heat_position(int calls, int max_calls) {
  if (max_calls < 1) max_calls = 1;
  return std::clamp(std::log2(1.0f + float(std::max(calls, 0))) / std::log2(1.0f + float(max_calls)), 0.0f, 1.0f);
}

} // namespace masq
