#include "hmt/grid/map_export.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <stdexcept>

#include "hmt/common/error.h"
#include "hmt/grid/png.h"
#include "hmt_test/scratch.h"

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

  const std::string dir = scratch::folder("map_export").string();
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

std::string read_bytes(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(f)), {});
}

// A grid over several bands of the writers, with occupied, free and unknown
// cells and a log-odds of every value.
OccupancyGrid varied_grid() {
  OccupancyGrid g(0.05);
  for (int y = -300; y < 420; y += 3)
    for (int x = -40; x < 90; x += 2)
      g.mutable_logodds({x, y}) = static_cast<LogOdds>(((x * 7 + y * 13) % 256) - 128);
  return g;
}

TEST(MapExport, StreamedImagesAreByteForByteTheWholeOnes) {
  const OccupancyGrid g = varied_grid();
  const MapImage whole = render(g, 10);
  const MapFrame f = map_frame(g, 10);
  EXPECT_EQ(f.width, whole.image.width());
  EXPECT_EQ(f.height, whole.image.height());
  EXPECT_GT(f.height, 600);  // several bands
  EXPECT_DOUBLE_EQ(f.origin_x, whole.origin_x);
  EXPECT_DOUBLE_EQ(f.origin_y, whole.origin_y);
  const std::string dir = scratch::folder("map_stream").string();
  write_png(whole, dir + "/whole.png");
  write_pgm_yaml(whole, dir + "/whole");
  MapRows png_rows(g, f);
  write_png_file(png_rows, dir + "/streamed.png");
  MapRows pgm_rows(g, f);
  write_pgm_yaml(pgm_rows, f, dir + "/streamed");
  EXPECT_EQ(read_bytes(dir + "/whole.png"), read_bytes(dir + "/streamed.png"));
  EXPECT_EQ(read_bytes(dir + "/whole.pgm"), read_bytes(dir + "/streamed.pgm"));
  std::string yaml = read_bytes(dir + "/streamed.yaml");
  EXPECT_EQ(yaml.find("image: streamed.pgm"), 0u);
  const cv::Mat back = cv::imread(dir + "/streamed.png", cv::IMREAD_GRAYSCALE);
  ASSERT_EQ(back.rows, f.height);
  for (int y = 0; y < back.rows; y += 37)
    for (int x = 0; x < back.cols; ++x)
      ASSERT_EQ(back.at<uint8_t>(y, x), whole.image.at(x, y)) << x << ", " << y;
}

// A source that fails part-way, as one that runs out of memory would.
class FailingRows : public BandRows {
 public:
  FailingRows() : BandRows(50, 40, 1, 8) {}

 protected:
  Image make_band(int first_row, int rows) override {
    if (first_row >= 16) throw std::runtime_error("band failed");
    return Image::band(50, 40, first_row, rows, 1, 128);
  }
};

TEST(MapExport, AFailingSourceLeavesTheEarlierFileIntact) {
  const std::string dir = scratch::folder("map_stream_fail").string();
  const MapImage m = render(varied_grid(), 0);
  write_png(m, dir + "/map.png");
  const std::string before = read_bytes(dir + "/map.png");
  FailingRows rows;
  try {
    write_png_file(rows, dir + "/map.png");
    FAIL() << "no error";
  } catch (const OutputError& e) {
    EXPECT_NE(std::string(e.what()).find("band failed"), std::string::npos) << e.what();
  }
  EXPECT_EQ(read_bytes(dir + "/map.png"), before);
  for (const auto& entry : std::filesystem::directory_iterator(dir))
    EXPECT_EQ(entry.path().filename().string().find(".tmp"), std::string::npos);
}

TEST(MapExport, UnwritableDirectoryIsOutputError) {
  OccupancyGrid g(0.1);
  EXPECT_THROW(write_png(render(g), "/nonexistent/dir/map.png"), std::exception);
}

}  // namespace
}  // namespace hmt::grid
