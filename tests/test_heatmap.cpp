// The heatmaps' scale and colour bar: one logarithmic scale that two methods' images
// share (issue 40: each heatmap used to be normalised to its own maximum, so ref's 927
// calls and masq's 7 looked alike), and a labelled bar below the image.
#include "image/heat_color.h"
#include "image/image_writer.h"
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>
#include <cmath>
#include <filesystem>

using namespace masq;

TEST(Heatmap, PositionIsLogarithmicOnAFixedScale) {
  EXPECT_EQ(heat_position(0, 1024), 0.0f);
  EXPECT_EQ(heat_position(1024, 1024), 1.0f);
  EXPECT_EQ(heat_position(5000, 1024), 1.0f); // above the scale: the top colour
  EXPECT_EQ(heat_position(-3, 1024), 0.0f);
  EXPECT_NEAR(heat_position(7, 1024), std::log2(8.0) / std::log2(1025.0), 1e-6);
  // Ref's 927 calls and masq's 7 land far apart on the same scale.
  EXPECT_GT(heat_position(927, 1024) - heat_position(7, 1024), 0.6f);
  for (int c = 0; c < 2000; ++c) EXPECT_LE(heat_position(c, 1024), heat_position(c + 1, 1024));
}

TEST(Heatmap, ImageGetsALabelledColourBar) {
  if (!image_output_built()) GTEST_SKIP() << "built without image output";
  const int w = 320, h = 40;
  std::vector<float> rgb(std::size_t(w) * h * 3, 0.5f);
  const std::string path = (std::filesystem::temp_directory_path() / "masq_test_heatmap.png").string();
  write_heatmap(path, w, h, rgb, 1024);
  auto in = OIIO::ImageInput::open(path);
  ASSERT_TRUE(in) << OIIO::geterror();
  const OIIO::ImageSpec& spec = in->spec();
  ASSERT_EQ(spec.width, w);
  ASSERT_GT(spec.height, h + 20); // the bar and its labels below the image
  std::vector<float> px(std::size_t(spec.width) * spec.height * 3);
  ASSERT_TRUE(in->read_image(0, 0, 0, 3, OIIO::TypeDesc::FLOAT, px.data()));
  auto at = [&](int x, int y, int c) { return px[(std::size_t(y) * spec.width + x) * 3 + c]; };
  EXPECT_NEAR(at(5, 5, 0), 0.5f, 0.01f); // the image itself, as given
  // The bar: black at its left end, white at its right end.
  const int bar = h + 4 + 6;
  EXPECT_LT(at(4, bar, 0) + at(4, bar, 1) + at(4, bar, 2), 0.1f);
  EXPECT_GT(at(w - 5, bar, 0) + at(w - 5, bar, 1) + at(w - 5, bar, 2), 2.9f);
  // Labels: dark text on the white band below the bar (DejaVu Sans, fonts-dejavu-core).
  int dark = 0;
  for (int y = h + 4 + 12; y < spec.height; ++y)
    for (int x = 0; x < w; ++x) dark += at(x, y, 0) < 0.3f;
  EXPECT_GT(dark, 50) << "no label drawn: is fonts-dejavu-core installed?";
  in->close();
  std::filesystem::remove(path);
}
