#pragma once
#include <string>
#include <vector>

namespace masq::cli {
// Writes an 8-bit RGB image (PNG, EXR, ... by extension) with OpenImageIO; throws on failure.
void write_rgb(const std::string& path, int width, int height, const std::vector<float>& rgb);
} // namespace masq::cli
