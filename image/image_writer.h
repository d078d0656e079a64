// Writing an image file: what `masq render` and the bench's heatmaps save.
#pragma once
#include <string>
#include <vector>

namespace masq {
// Writes an RGB image with OpenImageIO, the format by the extension (EXR as float, PNG
// and the others 8-bit); throws on failure, and in a build without image output
// (-DMASQ_WITH_IMAGES=OFF) always, naming the file and the build option.
void write_rgb(const std::string& path, int width, int height, const std::vector<float>& rgb);
// Writes a heatmap (rgb: width x height, from heat_color) with a colour bar below it: the
// ramp from 0 to max_calls calls on heat_position's scale, labelled at powers of two
// minus one (0, 1, 3, 7, ...) and at max_calls, so two heatmaps on one scale can be
// compared by eye. Labels need a TrueType font (DejaVu Sans, Debian's fonts-dejavu-core);
// without one the bar is drawn unlabelled. Throws as write_rgb does.
void write_heatmap(const std::string& path, int width, int height, const std::vector<float>& rgb, int max_calls);
// Whether this build writes images (false: built with -DMASQ_WITH_IMAGES=OFF).
bool image_output_built();
} // namespace masq
