// Writing an image file: what `masq render` and the bench's heatmaps save.
#pragma once
#include <string>
#include <vector>

namespace masq {
// Writes an RGB image with OpenImageIO, the format by the extension (EXR as float, PNG
// and the others 8-bit); throws on failure, and in a build without image output
// (-DMASQ_WITH_IMAGES=OFF) always, naming the file and the build option.
void write_rgb(const std::string& path, int width, int height, const std::vector<float>& rgb);
// Whether this build writes images (false: built with -DMASQ_WITH_IMAGES=OFF).
bool image_output_built();
} // namespace masq
