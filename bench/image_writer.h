#pragma once
#include <string>
#include <vector>

namespace masq {
// Writes an 8-bit RGB image (PNG, EXR, ... by extension) with OpenImageIO; throws on failure.
void write_rgb(const std::string& path, int width, int height, const std::vector<float>& rgb);
// Heat colour ramp for x in [0, 1]: black -> blue -> red -> yellow -> white.
void heat_color(float x, float* rgb);
} // namespace masq
