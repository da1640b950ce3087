#include "hmt/grid/png.h"

#include <gtest/gtest.h>
#include <png.h>

#include <cstring>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <random>

#include "hmt/common/error.h"
#include "hmt_test/scratch.h"

namespace hmt::grid {
namespace {

// Removed if the test passes.
std::string temp_dir() {
  return scratch::folder("png").string();
}

Image random_image(int width, int height, int channels, int seed) {
  Image m(width, height, channels);
  std::mt19937 rng(static_cast<uint32_t>(seed));
  for (int y = 0; y < height; ++y)
    for (int i = 0; i < width * channels; ++i)
      m.row(y)[i] = static_cast<uint8_t>(rng() & 0xFF);
  return m;
}

// OpenCV's decoder, an independent reader, gets the same pixels back (BGR
// too is OpenCV's order).
void expect_round_trip(const Image& image, const std::string& name) {
  const std::string path = temp_dir() + "/" + name;
  write_png_file(image, path);
  const cv::Mat back = cv::imread(path, cv::IMREAD_UNCHANGED);
  ASSERT_FALSE(back.empty()) << path;
  ASSERT_EQ(back.type(), CV_8UC(image.channels())) << path;
  ASSERT_EQ(back.cols, image.width()) << path;
  ASSERT_EQ(back.rows, image.height()) << path;
  for (int y = 0; y < image.height(); ++y)
    ASSERT_EQ(std::memcmp(back.ptr<uint8_t>(y), image.row(y),
                          static_cast<size_t>(image.width() * image.channels())),
              0)
        << path << " row " << y;
}

TEST(Png, GreyAndColourImagesRoundTrip) {
  expect_round_trip(random_image(53, 37, 1, 1), "grey.png");
  expect_round_trip(random_image(53, 37, 3, 2), "bgr.png");
  expect_round_trip(Image(1, 1, 1, 205), "pixel.png");
}

TEST(Png, ColourIsStoredAsRgbLikeOtherWriters) {
  // Pure blue, in memory as B, G, R.
  Image blue(3, 2, 3);
  for (int y = 0; y < 2; ++y)
    for (int x = 0; x < 3; ++x) blue.at(x, y, 0) = 255;
  const std::vector<uint8_t> bytes = encode_png(blue, "blue.png");
  ASSERT_GT(bytes.size(), 8u);
  EXPECT_EQ(std::string(bytes.begin(), bytes.begin() + 8),
            std::string("\x89PNG\r\n\x1a\n", 8));
  // Read as RGB by libpng itself: blue is the third component.
  png_image png;
  std::memset(&png, 0, sizeof png);
  png.version = PNG_IMAGE_VERSION;
  ASSERT_TRUE(png_image_begin_read_from_memory(&png, bytes.data(), bytes.size()))
      << png.message;
  EXPECT_EQ(png.width, 3u);
  EXPECT_EQ(png.height, 2u);
  png.format = PNG_FORMAT_RGB;
  std::vector<uint8_t> rgb(PNG_IMAGE_SIZE(png));
  ASSERT_TRUE(png_image_finish_read(&png, nullptr, rgb.data(), 0, nullptr)) << png.message;
  EXPECT_EQ(rgb[0], 0);
  EXPECT_EQ(rgb[1], 0);
  EXPECT_EQ(rgb[2], 255);
  // And OpenCV's reader turns it back into BGR blue.
  const cv::Mat back = cv::imdecode(bytes, cv::IMREAD_UNCHANGED);
  ASSERT_EQ(back.type(), CV_8UC3);
  EXPECT_EQ(back.at<cv::Vec3b>(0, 0), cv::Vec3b(255, 0, 0));
}

TEST(Png, EmptyImagesAndUnwritablePathsAreOutputErrors) {
  const std::string dir = temp_dir();
  EXPECT_THROW(write_png_file(Image(), dir + "/empty.png"), OutputError);
  EXPECT_THROW(write_png_file(Image(0, 4, 3), dir + "/flat.png"), OutputError);
  for (const char* f : {"empty.png", "flat.png"})
    EXPECT_FALSE(std::filesystem::exists(dir + "/" + f)) << f;
  try {
    write_png_file(Image(4, 4, 1), dir + "/missing/map.png");
    FAIL() << "no error";
  } catch (const OutputError& e) {
    EXPECT_NE(std::string(e.what()).find("missing/map.png"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(std::filesystem::exists(dir + "/missing"));
}

}  // namespace
}  // namespace hmt::grid
