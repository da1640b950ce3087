// ROS bags through the applications: log-to-bag writes the Edmonton CARMEN
// log as bags (odometry as nav_msgs/Odometry, and as /tf), and hmt-slam maps
// them exactly as it maps the log; convert turns a bag into a rawlog; bad
// bags and bad bag options end in one error line and their exit code.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "hmt/common/error.h"
#include "hmt/io/tum.h"
#include "run_app.h"

namespace hmt::e2e {
namespace {
namespace fs = std::filesystem;

AppResult log_to_bag(const std::string& args, const std::string& dir) {
  return run_binary(HMT_LOG_TO_BAG_BIN, args, dir);
}

std::string last_line(std::string s) {
  while (!s.empty() && s.back() == '\n') s.pop_back();
  const auto p = s.rfind('\n');
  return p == std::string::npos ? s : s.substr(p + 1);
}

void expect_error(const AppResult& r, ExitCode code, const std::string& mention) {
  EXPECT_EQ(r.exit_code, static_cast<int>(code)) << r.err;
  const std::string line = last_line(r.err);
  EXPECT_EQ(line.rfind("hmt-slam: error: ", 0), 0u) << r.err;
  EXPECT_NE(line.find(mention), std::string::npos) << line;
}

std::string edmonton_bag(const std::string& dir, const std::string& odometry) {
  const std::string bag = dir + "/edmonton_" + odometry + ".bag";
  const AppResult w = log_to_bag("--input datasets/edmonton.log.gz --output '" + bag +
                                     "' --odometry " + odometry, dir);
  EXPECT_EQ(w.exit_code, 0) << w.err;
  EXPECT_NE(w.out.find("340 scans"), std::string::npos) << w.out;
  return bag;
}

// The bags carry the log's odometry and scans bit for bit (the writer
// encodes each yaw so that it reads back exactly; see bag_writer.h), so the
// whole run is the same but for hmt_map.bin, which stores the scans'
// timestamps, held to the nanosecond in a bag.
TEST(RosBagApp, BagsOfTheEdmontonLogMapAsTheLogItself) {
  const std::string dir = temp_dir("rosbag_run");
  const AppResult c = run_app("run --config config/default.ini --quiet --input datasets/edmonton.log.gz "
                              "--out '" + dir + "/carmen'", dir);
  ASSERT_EQ(c.exit_code, 0) << c.err;
  for (const char* odometry : {"topic", "tf"}) {
    SCOPED_TRACE(odometry);
    const std::string bag = edmonton_bag(dir, odometry);
    const std::string out = dir + "/bag_" + odometry;
    const AppResult b = run_app("run --config config/default.ini --quiet --input '" + bag +
                                    "' --out '" + out + "'", dir);
    ASSERT_EQ(b.exit_code, 0) << b.err;
    for (const char* f : {"trajectory.tum", "map.pgm", "map.png", "map_topology.png",
                          "topology.json", "topology.dot", "tsbi_events.csv",
                          "topological_pmf.csv", "ess.csv", "config_effective.ini"}) {
      SCOPED_TRACE(f);
      const std::string a = slurp(dir + "/carmen/" + f);
      EXPECT_FALSE(a.empty());
      EXPECT_TRUE(a == slurp(out + "/" + f));
    }
    size_t areas = 0;
    for (const auto& e : fs::directory_iterator(dir + "/carmen/areas")) {
      ++areas;
      EXPECT_TRUE(slurp(e.path().string()) ==
                  slurp(out + "/areas/" + e.path().filename().string()))
          << e.path();
    }
    EXPECT_GT(areas, 3u);
  }
}

TEST(RosBagApp, ConvertTurnsABagIntoARawlog) {
  const std::string dir = temp_dir("rosbag_convert");
  const std::string bag = edmonton_bag(dir, "tf");
  const AppResult c = run_app("convert --input '" + bag + "' --output '" + dir +
                                  "/e.rawlog' --format obs --set input.odom_topic=tf", dir);
  ASSERT_EQ(c.exit_code, 0) << c.err;
  EXPECT_NE(c.out.find("340 scans"), std::string::npos) << c.out;
  const AppResult r = run_app("run --config config/default.ini --quiet --input '" + dir +
                                  "/e.rawlog' --set input.max_steps=40 --out '" + dir + "/o'", dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(io::read_tum(dir + "/o/trajectory.tum").size(), 40u);
  // Bag options are checked as in a run.
  expect_error(run_app("convert --input '" + bag + "' --output '" + dir +
                           "/x.rawlog' --set input.scan_topic=/front", dir),
               ExitCode::kInput, "no topic '/front'");
  expect_error(run_app("convert --input '" + bag + "' --output '" + dir +
                           "/x.rawlog' --set input.scan_topc=/scan", dir),
               ExitCode::kConfig, "scan_topc");
  EXPECT_FALSE(fs::exists(dir + "/x.rawlog"));
}

TEST(RosBagApp, BadBagsAndOptions) {
  const std::string dir = temp_dir("rosbag_errors");
  const std::string bag = edmonton_bag(dir, "topic");
  auto run = [&](const std::string& input, const std::string& sets) {
    return run_app("run --config config/default.ini --quiet --input '" + input + "' " + sets +
                       " --out '" + dir + "/out'", dir);
  };
  const std::string bytes = slurp(bag);
  std::ofstream(dir + "/cut.bag", std::ios::binary) << bytes.substr(0, bytes.size() / 2);
  expect_error(run(dir + "/cut.bag", ""), ExitCode::kInput, "cut.bag");
  expect_error(run(bag, "--set input.odom_topic=/wheels"), ExitCode::kInput, "no topic '/wheels'");
  expect_error(run(bag, "--set input.odom_topic=tf"), ExitCode::kInput, "no odometry");
  expect_error(run(bag, "--set input.scan_topic=/odom"), ExitCode::kInput,
               "is nav_msgs/Odometry, not sensor_msgs/LaserScan");
  expect_error(run(bag, "--set 'input.laser_pose=0.1 0'"), ExitCode::kConfig, "laser_pose");
  EXPECT_FALSE(fs::exists(dir + "/out/map.png"));
  // log-to-bag's own usage errors.
  const AppResult u = log_to_bag("--input datasets/edmonton.log.gz --output '" + dir +
                                     "/u.bag' --odometry wheels", dir);
  EXPECT_EQ(u.exit_code, static_cast<int>(ExitCode::kUsage)) << u.err;
  EXPECT_FALSE(fs::exists(dir + "/u.bag"));
}

}  // namespace
}  // namespace hmt::e2e
