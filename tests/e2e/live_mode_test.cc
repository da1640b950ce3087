// hmt-slam run in live mode: metric SLAM never waits for the topology, the
// log is replayed at its own pace (60 s), and TSBI's answers, a few steps
// late, are carried forward. Timing decides the details, not the outcome:
// the loop still closes. Its own executable, run alone (RUN_SERIAL): on a
// machine busy with other tests the replay would outrun the topology.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "hmt/io/tum.h"
#include "loop_closure.h"
#include "run_app.h"

namespace hmt::e2e {
namespace {

TEST(LiveMode, AtTheLogsOwnPaceTheLoopCloses) {
  const std::string dir = temp_dir("live");
  const AppResult r = run_app("run --config config/default.ini --quiet --set framework.mode=live "
                              "--set framework.live_speed=1 --out '" + dir + "/out'", dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  ASSERT_EQ(io::read_tum(dir + "/out/trajectory.tum").size(), 225u);
  const auto summary = nlohmann::json::parse(slurp(dir + "/out/summary.json"));
  EXPECT_EQ(summary["framework_mode"].get<std::string>(), "live");
  EXPECT_GE(summary["wall_time_s"].get<double>(), 55.0);  // paced by the log's clock
  expect_loop_closed_into_area_1(dir + "/out", 3);
}

}  // namespace
}  // namespace hmt::e2e
