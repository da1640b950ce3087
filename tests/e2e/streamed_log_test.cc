// `hmt-slam run` reads its log as it goes: a rawlog whose decoded scans are
// several times the memory bound runs within that bound (the whole log read
// up front would not fit). The log is a robot standing in a round room with
// a dense scanner: small on disk (gzip), large in memory, quick to run.
#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>

#include "hmt/io/rawlog.h"
#include "run_app.h"

namespace hmt::e2e {
namespace {

constexpr size_t kScans = 6000;
constexpr size_t kBeams = 10000;
// Peak resident memory allowed (MB): the run itself needs ~15 MB; the
// decoded log is kScans * kBeams * 5 bytes = 286 MB (the whole-log reader
// peaked at 156 MB with half as many scans).
constexpr double kBoundMb = 60.0;

hmt::Log standing_robot() {
  hmt::Log log;
  log.source = "standing robot";
  for (size_t k = 0; k < kScans; ++k) {
    LogStep s;
    s.timestamp = 0.1 * static_cast<double>(k);
    s.has_odometry = k > 0;
    s.scan.timestamp = s.timestamp;
    s.scan.angle_min = static_cast<float>(-M_PI / 2);
    s.scan.angle_increment = static_cast<float>(M_PI / (kBeams - 1));
    s.scan.max_range = 30.0f;
    s.scan.ranges.assign(kBeams, 4.0f);
    s.scan.valid.assign(kBeams, 1);
    log.steps.push_back(std::move(s));
  }
  return log;
}

TEST(StreamedLog, LongRawlogRunsInBoundedMemory) {
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
  GTEST_SKIP() << "sanitizer runtimes add their own memory: the bound is for the real build";
#endif
  const std::string dir = temp_dir("streamed_log");
  const std::string rawlog = dir + "/standing.rawlog.gz";
  hmt::io::write_rawlog(standing_robot(), rawlog, hmt::io::RawlogFormat::kObservationsOnly);
  const double decoded_mb = kScans * kBeams * 5.0 / (1024.0 * 1024.0);
  ASSERT_GT(decoded_mb, 4 * kBoundMb);

  const AppResult r = run_app("run --quiet --input '" + rawlog + "' --out '" + dir +
                                  "/out' --set metric_slam.particles=4 --set "
                                  "scan_matcher.beam_skip=99",
                              dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto summary = nlohmann::json::parse(slurp(dir + "/out/summary.json"));
  EXPECT_EQ(summary["scans"].get<size_t>(), kScans);
  const double peak_mb = summary["peak_rss_mb"].get<double>();
  EXPECT_LT(peak_mb, kBoundMb) << "decoded log " << decoded_mb << " MB";
}

}  // namespace
}  // namespace hmt::e2e
