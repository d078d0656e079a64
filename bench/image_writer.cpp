#include "bench/image_writer.h"
#include "scenes/error.h"
#include <OpenImageIO/imageio.h>
#include <algorithm>

namespace masq {

void write_rgb(const std::string& path, int width, int height, const std::vector<float>& rgb) {
  auto out = OIIO::ImageOutput::create(path);
  if (!out) throw Error("image: cannot write '" + path + "': " + OIIO::geterror());
  OIIO::ImageSpec spec(width, height, 3, path.ends_with(".exr") ? OIIO::TypeDesc::FLOAT : OIIO::TypeDesc::UINT8);
  if (!out->open(path, spec) || !out->write_image(OIIO::TypeDesc::FLOAT, rgb.data()) || !out->close())
    throw Error("image: writing '" + path + "' failed: " + out->geterror());
}

void heat_color(float x, float* rgb) {
  x = std::clamp(x, 0.0f, 1.0f);
  rgb[0] = std::clamp(3.0f * x - 1.0f, 0.0f, 1.0f);
  rgb[1] = std::clamp(3.0f * x - 2.0f, 0.0f, 1.0f);
  rgb[2] = std::clamp(x < 0.33f ? 3.0f * x : 2.0f - 3.0f * x, 0.0f, 1.0f) + std::clamp(3.0f * x - 2.0f, 0.0f, 1.0f);
}

} // namespace masq
