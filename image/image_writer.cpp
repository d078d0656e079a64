// write_rgb through OpenImageIO (EXR keeps float samples, every other format 8 bits).
#include "image/image_writer.h"
#include "masq/error.h"
#include "image/heat_color.h"
#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <OpenImageIO/imageio.h>
#include <algorithm>
#include <string>

namespace masq {

void write_rgb(const std::string& path, int width, int height, const std::vector<float>& rgb) {
  auto out = OIIO::ImageOutput::create(path);
  if (!out) throw Error("image: cannot write '" + path + "': " + OIIO::geterror());
  OIIO::ImageSpec spec(width, height, 3, path.ends_with(".exr") ? OIIO::TypeDesc::FLOAT : OIIO::TypeDesc::UINT8);
  if (!out->open(path, spec) || !out->write_image(OIIO::TypeDesc::FLOAT, rgb.data()) || !out->close())
    throw Error("image: writing '" + path + "' failed: " + out->geterror());
}

namespace {
constexpr int kBarHeight = 12, kLabelHeight = 16, kMargin = 4;

// The x of `calls` on a bar from x0 to x1.
int bar_x(int calls, int max_calls, int x0, int x1) {
  return x0 + int(heat_position(calls, max_calls) * float(x1 - x0 - 1) + 0.5f);
}
} // namespace

void write_heatmap(const std::string& path, int width, int height, const std::vector<float>& rgb, int max_calls) {
  const int legend = kMargin + kBarHeight + kLabelHeight + kMargin;
  const int full = height + legend;
  std::vector<float> out(std::size_t(width) * std::size_t(full) * 3, 1.0f); // white below the image
  std::copy(rgb.begin(), rgb.end(), out.begin());
  const int x0 = kMargin, x1 = std::max(x0 + 2, width - kMargin), y0 = height + kMargin;
  for (int x = x0; x < x1; ++x) {
    float c[3];
    heat_color(float(x - x0) / float(x1 - x0 - 1), c);
    for (int y = y0; y < y0 + kBarHeight; ++y) std::copy(c, c + 3, &out[(std::size_t(y) * width + x) * 3]);
  }
  OIIO::ImageBuf buf(OIIO::ImageSpec(width, full, 3, OIIO::TypeDesc::FLOAT), out.data());
  // Labels: the top ("N+ calls") at the right, then 0, 1, 3, 7, ... (evenly spaced on the
  // log scale) wherever they do not overlap. render_text fails without a font: the bar
  // stays unlabelled then (the caller prints the scale too).
  const float black[3] = {0.0f, 0.0f, 0.0f};
  const int baseline = y0 + kBarHeight + kLabelHeight - 3, glyph = 7; // DejaVu Sans at 12 px
  const std::string top = std::to_string(max_calls) + "+ calls";
  const int top_left = std::max(0, width - kMargin - glyph * int(top.size()));
  if (!OIIO::ImageBufAlgo::render_text(buf, top_left, baseline, top, 12, "DejaVuSans", black)) {
    write_rgb(path, width, full, out);
    return;
  }
  int last_right = -1000;
  for (int calls = 0; calls < max_calls; calls = 2 * calls + 1) {
    const std::string text = std::to_string(calls);
    const int w = glyph * int(text.size());
    const int left = std::max(0, bar_x(calls, max_calls, x0, x1) - w / 2);
    if (left < last_right + 6 || left + w > top_left - 6) continue;
    OIIO::ImageBufAlgo::render_text(buf, left, baseline, text, 12, "DejaVuSans", black);
    last_right = left + w;
  }
  write_rgb(path, width, full, out);
}

bool image_output_built() { return true; }

} // namespace masq
