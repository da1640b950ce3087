// hmt-slam run on the embedded log with the island-placement criterion
// (003 Eq. 3) deciding where areas start: the run completes and the loop is
// still closed into area 1 by inference.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "loop_closure.h"
#include "run_app.h"

namespace hmt::e2e {
namespace {

TEST(Placement, IslandPolicyClosesTheEmbeddedLoop) {
  const std::string dir = temp_dir("placement_islands");
  // The embedded log is outdoors (a campus loop): its scans see few walls
  // within placement_max_range, so their R stays under 0.1 and the indoor
  // threshold T = 0.5 would never accept a place; T = 0.05 suits it.
  const AppResult r = run_app(
      "run --config config/default.ini --quiet --set area.placement=islands"
      " --set area.placement_threshold=0.05 --out '" + dir + "/out'",
      dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto summary = nlohmann::json::parse(slurp(dir + "/out/summary.json"));
  EXPECT_EQ(summary["scans"].get<int>(), 225);
  // Eq. 3 fired at least once (else there is no loop to close) ...
  EXPECT_GE(summary["areas"].get<int>(), 2);
  EXPECT_GE(summary["loop_closures_accepted"].get<int>(), 1);
  // ... and the return to the start was recognised as area 1.
  expect_loop_closed_into_area_1(dir + "/out", 2);
}

}  // namespace
}  // namespace hmt::e2e
