#include "hmt/grid/png.h"

#include <gtest/gtest.h>
#include <png.h>

#include <cstring>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>

#include "hmt/common/error.h"

namespace hmt::grid {
namespace {

std::string temp_dir() {
  const std::string dir = testing::TempDir() + "/hmt_png";
  std::filesystem::create_directories(dir);
  return dir;
}

cv::Mat random_image(int rows, int cols, int type, int seed) {
  cv::Mat m(rows, cols, type);
  cv::RNG rng(static_cast<uint64_t>(seed));
  rng.fill(m, cv::RNG::UNIFORM, 0, 256);
  return m;
}

// OpenCV's decoder, an independent reader, gets the same pixels back.
void expect_round_trip(const cv::Mat& image, const std::string& name) {
  const std::string path = temp_dir() + "/" + name;
  write_png_file(image, path);
  const cv::Mat back = cv::imread(path, cv::IMREAD_UNCHANGED);
  ASSERT_FALSE(back.empty()) << path;
  ASSERT_EQ(back.type(), image.type()) << path;
  ASSERT_EQ(back.size(), image.size()) << path;
  EXPECT_EQ(cv::norm(image, back, cv::NORM_INF), 0.0) << path;
}

TEST(Png, GreyColourAndAlphaImagesRoundTrip) {
  expect_round_trip(random_image(37, 53, CV_8UC1, 1), "grey.png");
  expect_round_trip(random_image(37, 53, CV_8UC3, 2), "bgr.png");
  expect_round_trip(random_image(37, 53, CV_8UC4, 3), "bgra.png");
  expect_round_trip(cv::Mat(1, 1, CV_8UC1, cv::Scalar(205)), "pixel.png");
}

TEST(Png, ColourIsStoredAsRgbLikeOtherWriters) {
  // Pure blue in OpenCV's BGR order.
  const cv::Mat blue(2, 3, CV_8UC3, cv::Scalar(255, 0, 0));
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

TEST(Png, ASubImageIsWrittenWithItsOwnRows) {
  const cv::Mat big = random_image(40, 60, CV_8UC3, 4);
  const cv::Mat roi = big(cv::Rect(7, 5, 21, 13));  // rows apart by big's step
  ASSERT_FALSE(roi.isContinuous());
  expect_round_trip(roi, "roi.png");
}

TEST(Png, UnsupportedImagesAndUnwritablePathsAreOutputErrors) {
  const std::string dir = temp_dir();
  EXPECT_THROW(write_png_file(cv::Mat(), dir + "/empty.png"), OutputError);
  EXPECT_THROW(write_png_file(cv::Mat(4, 4, CV_16UC1, cv::Scalar(0)), dir + "/deep.png"),
               OutputError);
  EXPECT_THROW(write_png_file(cv::Mat(4, 4, CV_8UC2, cv::Scalar(0)), dir + "/two.png"),
               OutputError);
  for (const char* f : {"empty.png", "deep.png", "two.png"})
    EXPECT_FALSE(std::filesystem::exists(dir + "/" + f)) << f;
  try {
    write_png_file(cv::Mat(4, 4, CV_8UC1, cv::Scalar(0)), dir + "/missing/map.png");
    FAIL() << "no error";
  } catch (const OutputError& e) {
    EXPECT_NE(std::string(e.what()).find("missing/map.png"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(std::filesystem::exists(dir + "/missing"));
}

}  // namespace
}  // namespace hmt::grid
