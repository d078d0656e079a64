// heat_color: three overlapping linear ramps, clamped.
#include "image/heat_color.h"
#include <algorithm>

namespace masq {

void heat_color(float x, float* rgb) {
  x = std::clamp(x, 0.0f, 1.0f);
  rgb[0] = std::clamp(3.0f * x - 1.0f, 0.0f, 1.0f);
  rgb[1] = std::clamp(3.0f * x - 2.0f, 0.0f, 1.0f);
  rgb[2] = std::clamp(x < 0.33f ? 3.0f * x : 2.0f - 3.0f * x, 0.0f, 1.0f) + std::clamp(3.0f * x - 2.0f, 0.0f, 1.0f);
}

} // namespace masq
