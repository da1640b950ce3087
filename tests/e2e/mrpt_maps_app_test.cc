// `[output] mrpt_maps = true` through hmt-slam, the files read back by MRPT:
// the grid map is map.pgm's map cell for cell, and the simple map holds the
// keyframes the map was drawn from, at the trajectory's poses.
#include <gtest/gtest.h>
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/maps/COccupancyGridMap2D.h>
#include <mrpt/maps/CSimpleMap.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/poses/CPose3DPDFGaussian.h>
#include <mrpt/serialization/CArchive.h>
#include <nlohmann/json.hpp>

#include "hmt/common/config.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <map>
#include <sstream>

#include "hmt/io/tum.h"
#include "run_app.h"

namespace hmt::e2e {
namespace {

struct Pgm {
  int width = 0, height = 0;
  std::string pixels;  // row 0 is the top (largest y)
};

// A binary PGM ("P5", comment lines, width, height, maxval, one byte each).
Pgm read_pgm(const std::string& path) {
  const std::string bytes = slurp(path);
  size_t at = 0;
  auto token = [&] {
    while (at < bytes.size()) {
      if (bytes[at] == '#') {
        while (at < bytes.size() && bytes[at] != '\n') ++at;
      } else if (std::isspace(static_cast<unsigned char>(bytes[at]))) {
        ++at;
      } else {
        break;
      }
    }
    const size_t begin = at;
    while (at < bytes.size() && !std::isspace(static_cast<unsigned char>(bytes[at]))) ++at;
    return bytes.substr(begin, at - begin);
  };
  Pgm p;
  EXPECT_EQ(token(), "P5");
  p.width = std::stoi(token());
  p.height = std::stoi(token());
  EXPECT_EQ(token(), "255");
  p.pixels = bytes.substr(at + 1);  // one whitespace after maxval
  EXPECT_EQ(p.pixels.size(), static_cast<size_t>(p.width) * p.height);
  return p;
}

// Checks every keyframe of OUT/keyframes.simplemap against the run's
// trajectory (a keyframe's step is placed at the keyframe's pose) and
// returns how many there are.
size_t check_keyframes(const std::string& out) {
  mrpt::maps::CSimpleMap keyframes;
  EXPECT_TRUE(keyframes.loadFromFile(out + "/keyframes.simplemap"));
  std::map<long long, Pose2D> traj;  // by the timestamp in microseconds
  for (const io::StampedPose& s : io::read_tum(out + "/trajectory.tum"))
    traj[std::llround(s.timestamp * 1e6)] = s.pose;
  for (size_t i = 0; i < keyframes.size(); ++i) {
    SCOPED_TRACE(i);
    const auto [pdf, frame] = keyframes.get(i);
    const auto pose = std::dynamic_pointer_cast<mrpt::poses::CPose3DPDFGaussian>(pdf);
    EXPECT_TRUE(pose && frame);
    if (!pose || !frame) continue;
    const auto scan = frame->getObservationByClass<mrpt::obs::CObservation2DRangeScan>();
    EXPECT_TRUE(scan);
    if (!scan) continue;
    EXPECT_GT(scan->getScanSize(), 100u);
    // trajectory.tum rounds to microseconds, MRPT keeps 100 ns ticks.
    const long long us = std::llround(mrpt::Clock::toDouble(scan->timestamp) * 1e6);
    const auto t = traj.lower_bound(us - 1);
    EXPECT_TRUE(t != traj.end() && t->first <= us + 1) << us;
    if (t == traj.end()) continue;
    EXPECT_NEAR(pose->mean.x(), t->second.x, 1e-3);
    EXPECT_NEAR(pose->mean.y(), t->second.y, 1e-3);
    EXPECT_NEAR(std::remainder(pose->mean.yaw() - t->second.theta, 2 * M_PI), 0.0, 1e-3);
    // A proper covariance of x, y and yaw.
    EXPECT_GT(pose->cov(0, 0), 0.0);
    EXPECT_GT(pose->cov(1, 1), 0.0);
    EXPECT_GT(pose->cov(3, 3), 0.0);
    EXPECT_LT(pose->cov(0, 0), 1.0);
  }
  return keyframes.size();
}

TEST(MrptMapsApp, MalagaMapsReadBackInMrpt) {
  const std::string dir = temp_dir("mrpt_maps");
  const AppResult r = run_app(
      "run --quiet --set output.mrpt_maps=true --set output.png=false --out '" + dir + "/out'",
      dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string out = dir + "/out";

  // The grid: map.pgm's size, resolution and origin, and its cells.
  mrpt::maps::COccupancyGridMap2D grid;
  {
    mrpt::io::CFileGZInputStream in;
    ASSERT_TRUE(in.open(out + "/map.gridmap.gz"));
    mrpt::serialization::archiveFrom(in) >> grid;
  }
  const Pgm pgm = read_pgm(out + "/map.pgm");
  ASSERT_EQ(static_cast<int>(grid.getSizeX()), pgm.width);
  ASSERT_EQ(static_cast<int>(grid.getSizeY()), pgm.height);
  EXPECT_NEAR(grid.getResolution(), 0.05, 1e-6);
  const std::string yaml = slurp(out + "/map.yaml");
  double ox = 0, oy = 0;
  ASSERT_EQ(std::sscanf(yaml.substr(yaml.find("origin:")).c_str(), "origin: [%lf, %lf", &ox, &oy),
            2);
  EXPECT_NEAR(grid.getXMin(), ox, 1e-4);
  EXPECT_NEAR(grid.getYMin(), oy, 1e-4);
  size_t occupied = 0, free = 0, unknown = 0;
  for (int row = 0; row < pgm.height; ++row)
    for (int col = 0; col < pgm.width; ++col) {
      const int grey = static_cast<unsigned char>(pgm.pixels[row * pgm.width + col]);
      const double p_mrpt = 1.0 - grid.getCell(col, pgm.height - 1 - row);
      if (grey == 205) {  // unknown (or P(occupied) of 0.193)
        ++unknown;
        EXPECT_TRUE(std::abs(p_mrpt - 0.5) < 0.01 || std::abs(p_mrpt - 0.193) < 0.01)
            << col << ", " << row << ": " << p_mrpt;
        continue;
      }
      const double p_pgm = 1.0 - grey / 254.0;
      ASSERT_NEAR(p_mrpt, p_pgm, 0.02) << "cell " << col << ", " << row;
      if (p_pgm > 0.65) ++occupied;
      if (p_pgm < 0.196) ++free;
    }
  EXPECT_GT(occupied, 1000u);
  EXPECT_GT(free, 10000u);
  EXPECT_GT(unknown, 1000u);

  // The keyframes: those of the keyframe graph, at the trajectory's poses.
  const auto summary = nlohmann::json::parse(slurp(out + "/summary.json"));
  const size_t nodes = summary["global_map"]["keyframe_graph"]["keyframe_nodes"].get<size_t>();
  EXPECT_GT(nodes, 20u);
  EXPECT_EQ(check_keyframes(out), nodes);
  // Whether its rounds settled: ended early with no keyframe moved by more
  // than the tolerance in the last one, or ran them all (the run's own
  // [global_map] rounds and round_tolerance).
  hmt::Config effective = hmt::Config::from_file(out + "/config_effective.ini");
  ASSERT_TRUE(effective.has("global_map", "rounds"));
  ASSERT_TRUE(effective.has("global_map", "round_tolerance"));
  const int rounds = effective.get_int("global_map", "rounds", 0);
  const double tolerance = effective.get_double("global_map", "round_tolerance", 0.0);
  const auto& graph = summary["global_map"]["keyframe_graph"];
  const double move = graph["last_round_move_m"].get<double>();
  const double turn = graph["last_round_move_rad"].get<double>();
  EXPECT_GE(move, 0.0);
  EXPECT_GE(turn, 0.0);
  if (graph["converged"].get<bool>()) {
    EXPECT_LE(graph["rounds"].get<int>(), rounds);
    EXPECT_LE(std::max(move, turn), tolerance);
  } else {
    EXPECT_EQ(graph["rounds"].get<int>(), rounds);
    EXPECT_GT(std::max(move, turn), tolerance);
  }

  // Same log, config and seed: the same bytes (zlib's gzip header holds no
  // time), whatever the particle threads.
  const AppResult again = run_app("run --quiet --set output.mrpt_maps=true --set output.png=false "
                                  "--set metric_slam.threads=1 --out '" + dir + "/again'",
                                  dir);
  ASSERT_EQ(again.exit_code, 0) << again.err;
  for (const char* f : {"map.gridmap.gz", "keyframes.simplemap"})
    EXPECT_EQ(slurp(out + "/" + f), slurp(dir + "/again/" + f)) << f;
}

// [global_map] method = areas: no keyframe graph; the keyframes are taken
// along the area visits, every [hmt] keyframe_distance / keyframe_angle.
TEST(MrptMapsApp, AreasMethodKeyframesFollowTheTrajectory) {
  const std::string dir = temp_dir("mrpt_maps_areas");
  const AppResult r = run_app("run --quiet --set output.mrpt_maps=true --set output.png=false "
                              "--set global_map.method=areas --out '" + dir + "/out'",
                              dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_GT(check_keyframes(dir + "/out"), 20u);
  mrpt::maps::COccupancyGridMap2D grid;
  {
    mrpt::io::CFileGZInputStream in;
    ASSERT_TRUE(in.open(dir + "/out/map.gridmap.gz"));
    mrpt::serialization::archiveFrom(in) >> grid;
  }
  const Pgm pgm = read_pgm(dir + "/out/map.pgm");
  EXPECT_EQ(static_cast<int>(grid.getSizeX()), pgm.width);
  EXPECT_EQ(static_cast<int>(grid.getSizeY()), pgm.height);
}

}  // namespace
}  // namespace hmt::e2e
