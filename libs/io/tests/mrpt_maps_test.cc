// The MRPT map files, read back by MRPT itself: the grid map's size,
// resolution, origin and cells, the simple map's keyframes (poses with their
// covariance, scans) as MRPT's tools will see them.
#include "hmt/io/mrpt_maps.h"

#include <gtest/gtest.h>
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/maps/COccupancyGridMap2D.h>
#include <mrpt/maps/CSimpleMap.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/poses/CPose3DPDFGaussian.h>
#include <mrpt/serialization/CArchive.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "hmt/common/error.h"
#include "hmt_test/scratch.h"

namespace hmt::io {
namespace {
namespace fs = std::filesystem;

// A fresh folder, removed if the test passes.
std::string temp_dir(const std::string& name) {
  return scratch::folder("mrpt_maps_" + name).string();
}

std::string slurp(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

template <typename Object>
void load_gz(Object& object, const std::string& path) {
  mrpt::io::CFileGZInputStream in;
  ASSERT_TRUE(in.open(path)) << path;
  auto archive = mrpt::serialization::archiveFrom(in);
  archive >> object;
}

// 40 x 30 cells of 0.1 m from (-1.5, 2.0): a wall along cy = 20, free
// space below it, unknown above; one cell in between.
MrptGridMap test_grid() {
  MrptGridMap g;
  g.resolution = 0.1;
  g.x_min = -1.5;
  g.y_min = 2.0;
  g.size_x = 40;
  g.size_y = 30;
  g.occupancy = [](int cx, int cy) -> float {
    if (cx == 7 && cy == 25) return 0.75f;
    if (cy == 20) return 0.95f;
    return cy < 20 ? 0.1f : 0.5f;
  };
  return g;
}

TEST(MrptMaps, GridMapReadsBackInMrpt) {
  const std::string dir = temp_dir("grid");
  const std::string path = dir + "/map.gridmap.gz";
  write_mrpt_gridmap(test_grid(), path);
  // gzip, as CFileGZOutputStream writes it.
  const std::string bytes = slurp(path);
  ASSERT_GT(bytes.size(), 2u);
  EXPECT_EQ(static_cast<unsigned char>(bytes[0]), 0x1f);
  EXPECT_EQ(static_cast<unsigned char>(bytes[1]), 0x8b);

  mrpt::maps::COccupancyGridMap2D grid;
  load_gz(grid, path);
  EXPECT_EQ(grid.getSizeX(), 40u);
  EXPECT_EQ(grid.getSizeY(), 30u);
  EXPECT_NEAR(grid.getResolution(), 0.1, 1e-6);
  EXPECT_NEAR(grid.getXMin(), -1.5, 1e-5);
  EXPECT_NEAR(grid.getYMin(), 2.0, 1e-5);
  EXPECT_NEAR(grid.getXMax(), 2.5, 1e-5);
  EXPECT_NEAR(grid.getYMax(), 5.0, 1e-5);
  // MRPT's cells hold P(free), quantized to its 8-bit log-odds.
  EXPECT_NEAR(1.0 - grid.getCell(3, 20), 0.95, 0.01);
  EXPECT_NEAR(1.0 - grid.getCell(39, 20), 0.95, 0.01);
  EXPECT_NEAR(1.0 - grid.getCell(0, 0), 0.1, 0.01);
  EXPECT_NEAR(1.0 - grid.getCell(12, 19), 0.1, 0.01);
  EXPECT_NEAR(grid.getCell(12, 29), 0.5, 0.01);
  EXPECT_NEAR(1.0 - grid.getCell(7, 25), 0.75, 0.01);
  // By position: cell (7, 25) is [-0.8, -0.7) x [4.5, 4.6).
  EXPECT_NEAR(1.0 - grid.getPos(-0.75f, 4.55f), 0.75, 0.01);
  EXPECT_NEAR(grid.getPos(-0.65f, 4.55f), 0.5, 0.01);
  // MRPT's own reading of what is an obstacle.
  EXPECT_TRUE(grid.isStaticCell(20, 20, 0.3f));
  EXPECT_FALSE(grid.isStaticCell(20, 10, 0.3f));
}

LaserScan test_scan(double t, float range) {
  LaserScan s;
  s.timestamp = t;
  s.angle_min = static_cast<float>(-M_PI / 2);
  s.angle_increment = static_cast<float>(M_PI / 180);
  s.max_range = 30.0f;
  s.sensor_pose = Pose2D(0.2, 0.0, 0.0);
  for (int i = 0; i < 181; ++i) {
    s.ranges.push_back(range + 0.01f * static_cast<float>(i));
    s.valid.push_back(i % 10 != 3);
  }
  return s;
}

TEST(MrptMaps, SimpleMapReadsBackInMrpt) {
  const std::string dir = temp_dir("simple");
  const std::string path = dir + "/keyframes.simplemap";
  std::vector<MapKeyframe> kfs;
  for (int i = 0; i < 3; ++i) {
    MapKeyframe k;
    k.pose.mean = Pose2D(1.0 + i, -0.5 * i, 0.3 * i - 0.2);
    k.pose.cov = Eigen::Matrix3d::Identity() * 0.01 * (i + 1);
    k.pose.cov(0, 1) = k.pose.cov(1, 0) = 0.001;
    k.pose.cov(0, 2) = k.pose.cov(2, 0) = 0.002;
    k.scan = test_scan(1.3e9 + i, 2.0f + i);
    kfs.push_back(k);
  }
  write_mrpt_simplemap(kfs, path);

  mrpt::maps::CSimpleMap map;
  ASSERT_TRUE(map.loadFromFile(path));  // what pf-localization and RawLogViewer call
  ASSERT_EQ(map.size(), 3u);
  for (size_t i = 0; i < map.size(); ++i) {
    SCOPED_TRACE(i);
    const auto [pdf, frame] = map.get(i);
    const auto gauss = std::dynamic_pointer_cast<mrpt::poses::CPose3DPDFGaussian>(pdf);
    ASSERT_TRUE(gauss);
    EXPECT_NEAR(gauss->mean.x(), kfs[i].pose.mean.x, 1e-9);
    EXPECT_NEAR(gauss->mean.y(), kfs[i].pose.mean.y, 1e-9);
    EXPECT_NEAR(gauss->mean.yaw(), kfs[i].pose.mean.theta, 1e-9);
    EXPECT_NEAR(gauss->mean.z(), 0.0, 1e-12);
    EXPECT_NEAR(gauss->mean.pitch(), 0.0, 1e-12);
    EXPECT_NEAR(gauss->mean.roll(), 0.0, 1e-12);
    // (x, y, yaw) are entries 0, 1, 3 of MRPT's (x, y, z, yaw, pitch, roll).
    EXPECT_NEAR(gauss->cov(0, 0), kfs[i].pose.cov(0, 0), 1e-12);
    EXPECT_NEAR(gauss->cov(1, 1), kfs[i].pose.cov(1, 1), 1e-12);
    EXPECT_NEAR(gauss->cov(3, 3), kfs[i].pose.cov(2, 2), 1e-12);
    EXPECT_NEAR(gauss->cov(0, 1), 0.001, 1e-12);
    EXPECT_NEAR(gauss->cov(0, 3), 0.002, 1e-12);
    EXPECT_NEAR(gauss->cov(2, 2), 0.0, 1e-12);
    ASSERT_TRUE(frame);
    ASSERT_EQ(frame->size(), 1u);
    const auto scan = frame->getObservationByClass<mrpt::obs::CObservation2DRangeScan>();
    ASSERT_TRUE(scan);
    ASSERT_EQ(scan->getScanSize(), 181u);
    EXPECT_NEAR(scan->aperture, M_PI, 1e-5);
    EXPECT_TRUE(scan->rightToLeft);
    EXPECT_FLOAT_EQ(scan->maxRange, 30.0f);
    EXPECT_NEAR(scan->sensorPose.x(), 0.2, 1e-9);
    EXPECT_FLOAT_EQ(scan->getScanRange(0), kfs[i].scan.ranges[0]);
    EXPECT_FLOAT_EQ(scan->getScanRange(100), kfs[i].scan.ranges[100]);
    EXPECT_FALSE(scan->getScanRangeValidity(3));
    EXPECT_TRUE(scan->getScanRangeValidity(4));
    EXPECT_NEAR(mrpt::Clock::toDouble(scan->timestamp), kfs[i].scan.timestamp, 1e-6);
  }
}

TEST(MrptMaps, BadInputIsAnErrorAndNoFile) {
  const std::string dir = temp_dir("bad");
  MrptGridMap empty = test_grid();
  empty.size_x = 0;
  EXPECT_THROW(write_mrpt_gridmap(empty, dir + "/a.gridmap.gz"), std::invalid_argument);
  MrptGridMap flat = test_grid();
  flat.resolution = 0.0;
  EXPECT_THROW(write_mrpt_gridmap(flat, dir + "/a.gridmap.gz"), std::invalid_argument);
  std::vector<MapKeyframe> kfs(1);
  EXPECT_THROW(write_mrpt_simplemap(kfs, dir + "/a.simplemap"), std::invalid_argument);
  EXPECT_TRUE(fs::is_empty(dir));
  // A folder that does not exist: an OutputError naming the file.
  try {
    write_mrpt_gridmap(test_grid(), dir + "/none/map.gridmap.gz");
    FAIL() << "expected OutputError";
  } catch (const OutputError& e) {
    EXPECT_NE(std::string(e.what()).find("none/map.gridmap.gz"), std::string::npos) << e.what();
  }
}

// Without the plugin, nothing is written and an earlier file stays whole.
TEST(MrptMaps, MissingPluginLeavesAnEarlierFileAlone) {
  const std::string dir = temp_dir("plugin");
  const std::string path = dir + "/map.gridmap.gz";
  write_mrpt_gridmap(test_grid(), path);
  const std::string before = slurp(path);
  ::setenv("HMT_IO_MRPT_MAPS_PLUGIN", (dir + "/no_such_plugin.so").c_str(), 1);
  try {
    write_mrpt_gridmap(test_grid(), path);
    ::unsetenv("HMT_IO_MRPT_MAPS_PLUGIN");
    FAIL() << "expected OutputError";
  } catch (const OutputError& e) {
    ::unsetenv("HMT_IO_MRPT_MAPS_PLUGIN");
    EXPECT_NE(std::string(e.what()).find("no_such_plugin.so"), std::string::npos) << e.what();
  }
  EXPECT_EQ(slurp(path), before);
  EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 1);
}

}  // namespace
}  // namespace hmt::io
