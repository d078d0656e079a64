// write_rgb of a build without image output (-DMASQ_WITH_IMAGES=OFF: the GPU bundle,
// scripts/gpu_bundle.sh): every image is refused with one line naming it.
#include "image/image_writer.h"
#include "masq/error.h"

namespace masq {

void write_rgb(const std::string& path, int, int, const std::vector<float>&) {
  throw Error("image: '" + path + "' not written: this masq was built without image output (-DMASQ_WITH_IMAGES=OFF)");
}

void write_heatmap(const std::string& path, int width, int height, const std::vector<float>& rgb, int) {
  write_rgb(path, width, height, rgb);
}

bool image_output_built() { return false; }

} // namespace masq
