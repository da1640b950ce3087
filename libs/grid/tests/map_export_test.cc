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
  EXPECT_EQ(m.image.cols, kTileSize);
  EXPECT_EQ(m.image.rows, kTileSize);
  EXPECT_DOUBLE_EQ(m.origin_x, 0.0);
  // Cell (0,0) is at the bottom-left pixel.
  EXPECT_LT(m.image.at<uint8_t>(kTileSize - 1, 0), 20);
  EXPECT_GT(m.image.at<uint8_t>(kTileSize - 1, 1), 230);
  EXPECT_EQ(m.image.at<uint8_t>(0, 5), 205);

  const std::string dir = testing::TempDir() + "/hmt_map_export";
  std::filesystem::create_directories(dir);
  write_png(m, dir + "/map.png");
  write_pgm_yaml(m, dir + "/map");
  const cv::Mat png = cv::imread(dir + "/map.png", cv::IMREAD_GRAYSCALE);
  const cv::Mat pgm = cv::imread(dir + "/map.pgm", cv::IMREAD_GRAYSCALE);
  ASSERT_FALSE(png.empty());
  ASSERT_FALSE(pgm.empty());
  EXPECT_EQ(cv::norm(png, pgm, cv::NORM_INF), 0.0);
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
