#include "hmt/experiments/fov_experiment.h"

#include <gtest/gtest.h>

namespace hmt::experiments {
namespace {

TEST(experiments_FieldOfView, NarrowerSensorMoreAreasOnASmallRoute) {
  FovOptions o;
  o.taus = {1.0};
  o.area.sso.use_probabilistic = false;  // the fixed delta of 001 Eq. 16
  const auto poses = route_poses(two_rooms_route(), o.step, o.turn_step);
  const auto results = run_field_of_view(two_rooms(), poses, standard_sensors(20.0), o);
  ASSERT_EQ(results.size(), 3u);
  const FovResult& wide = results[0];
  const FovResult& half = results[1];
  const FovResult& narrow = results[2];
  EXPECT_EQ(wide.sensor, "360deg");
  EXPECT_EQ(narrow.sensor, "65deg");
  for (const FovResult& r : results) {
    EXPECT_EQ(r.keyframes, static_cast<int>(poses.size()));
    EXPECT_EQ(r.labels.size(), poses.size());
    EXPECT_GE(r.areas, 1);
  }
  EXPECT_GE(half.areas, wide.areas);
  EXPECT_GT(narrow.areas, wide.areas);
  EXPECT_GT(narrow.areas, half.areas);
  // A wider view overlaps with more keyframes.
  EXPECT_GT(wide.mean_degree, narrow.mean_degree);
}

TEST(experiments_FieldOfView, OneResultPerSensorAndTau) {
  FovOptions o;
  o.taus = {0.5, 1.0};
  const auto poses = route_poses(two_rooms_route(), 1.0, o.turn_step);
  const auto results =
      run_field_of_view(two_rooms(), poses, {standard_sensors()[0]}, o);
  ASSERT_EQ(results.size(), 2u);
  EXPECT_EQ(results[0].tau, 0.5);
  EXPECT_EQ(results[1].tau, 1.0);
  // Lower tau: the same bisections or fewer.
  EXPECT_LE(results[0].areas, results[1].areas);
  o.taus = {};
  EXPECT_THROW(run_field_of_view(two_rooms(), poses, {}, o), std::invalid_argument);
}

}  // namespace
}  // namespace hmt::experiments
