#include "hmt/grid/map_export.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>

namespace hmt::grid {
namespace {

TEST(MapExport, PgmYamlAndPngAgree) {
  OccupancyGrid g(0.1);
  g.mutable_logodds({0, 0}) = 100;   // occupied
  g.mutable_logodds({1, 0}) = -100;  // free
  const MapImage m = render(g, 0);
  EXPECT_EQ(m.image.width(), kTileSize);
  EXPECT_EQ(m.image.height(), kTileSize);
  EXPECT_EQ(m.image.channels(), 1);
  EXPECT_DOUBLE_EQ(m.origin_x, 0.0);
  // Cell (0,0) is at the bottom-left pixel.
  EXPECT_LT(m.image.at(0, kTileSize - 1), 20);
  EXPECT_GT(m.image.at(1, kTileSize - 1), 230);
  EXPECT_EQ(m.image.at(5, 0), 205);

  const std::string dir = testing::TempDir() + "/hmt_map_export";
  std::filesystem::create_directories(dir);
  write_png(m, dir + "/map.png");
  write_pgm_yaml(m, dir + "/map");
  const cv::Mat png = cv::imread(dir + "/map.png", cv::IMREAD_GRAYSCALE);
  const cv::Mat pgm = cv::imread(dir + "/map.pgm", cv::IMREAD_GRAYSCALE);
  ASSERT_FALSE(png.empty());
  ASSERT_FALSE(pgm.empty());
  EXPECT_EQ(cv::norm(png, pgm, cv::NORM_INF), 0.0);
  ASSERT_EQ(png.cols, m.image.width());
  for (int y = 0; y < png.rows; ++y)
    for (int x = 0; x < png.cols; ++x)
      ASSERT_EQ(png.at<uint8_t>(y, x), m.image.at(x, y)) << x << ", " << y;
  std::ifstream y(dir + "/map.yaml");
  std::string yaml((std::istreambuf_iterator<char>(y)), {});
  EXPECT_NE(yaml.find("image: map.pgm"), std::string::npos);
  EXPECT_NE(yaml.find("resolution: 0.100000"), std::string::npos);
}

TEST(MapExport, UnwritableDirectoryIsOutputError) {
  OccupancyGrid g(0.1);
  EXPECT_THROW(write_png(render(g), "/nonexistent/dir/map.png"), std::exception);
}

}  // namespace
}  // namespace hmt::grid
