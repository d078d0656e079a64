// write_rgb through OpenImageIO (EXR keeps float samples, every other format 8 bits).
#include "image/image_writer.h"
#include "masq/error.h"
#include <OpenImageIO/imageio.h>

namespace masq {

void write_rgb(const std::string& path, int width, int height, const std::vector<float>& rgb) {
  auto out = OIIO::ImageOutput::create(path);
  if (!out) throw Error("image: cannot write '" + path + "': " + OIIO::geterror());
  OIIO::ImageSpec spec(width, height, 3, path.ends_with(".exr") ? OIIO::TypeDesc::FLOAT : OIIO::TypeDesc::UINT8);
  if (!out->open(path, spec) || !out->write_image(OIIO::TypeDesc::FLOAT, rgb.data()) || !out->close())
    throw Error("image: writing '" + path + "' failed: " + out->geterror());
}

bool image_output_built() { return true; }

} // namespace masq
