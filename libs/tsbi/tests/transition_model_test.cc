#include "hmt/tsbi/transition_model.h"

#include <gtest/gtest.h>

#include <memory>

#include "../../metric_slam/tests/sim_world.h"
#include "hmt/grid/scan_insertion.h"
#include "hmt/tsbi/observations.h"

namespace hmt::tsbi {
namespace {

using topology::AreaId;
using topology::HmtMap;
using topology::PoseGaussian;

LaserScan scan_at(const std::vector<testing_sim::Segment>& world, const Pose2D& p) {
  return testing_sim::cast_scan(world, p, 361, M_PI, 30.0, nullptr, 0.0);
}

// A map of `world` in the frame whose origin is the world pose `origin`,
// from scans taken at the given world poses.
std::shared_ptr<const grid::OccupancyGrid> map_of(
    const std::vector<testing_sim::Segment>& world, const Pose2D& origin,
    const std::vector<Pose2D>& poses) {
  auto g = std::make_shared<grid::OccupancyGrid>(0.05);
  for (const Pose2D& p : poses)
    grid::insert_scan(*g, p - origin, scan_at(world, p), grid::InsertionOptions{});
  return g;
}

Eigen::Matrix3d diag(double sxy, double sth) {
  return Eigen::Vector3d(sxy * sxy, sxy * sxy, sth * sth).asDiagonal();
}

// Area 1: the left part of the office (frame = world). Area 2: its right
// part, frame at world (10, 2, 0.3). Area 3, the current one: frame at world
// (4, 5, 1.0), never mapped here. Arcs carry the true relative poses with
// some uncertainty.
struct TwoKnownAreas {
  HmtMap map;
  Pose2D origin2{10, 2, 0.3}, origin3{4, 5, 1.0};
  TwoKnownAreas() {
    const auto world = testing_sim::office_world();
    map.add_area(1);
    map.add_area(2, {1, origin2, 0, 0});
    map.add_area(3, {2, origin3 - origin2, 0, 0});
    map.set_map(1, map_of(world, Pose2D(), {{2, 2, 0}, {4, 4, 1.5}, {6, 8, 3.0}, {2, 8, -1.5}}));
    map.set_map(2, map_of(world, origin2, {{12, 3, 0}, {17, 5, 1.5}, {12, 8, 3.0}}));
    map.add_arc_measurement(1, 2, PoseGaussian(origin2, diag(0.05, 0.02)));
    map.add_arc_measurement(2, 3, PoseGaussian(origin3 - origin2, diag(0.05, 0.02)));
  }
};

TransitionModel model(double log_eta = 10.0) {
  TsbiOptions o;
  o.log_eta = log_eta;
  return TransitionModel(o, metric_slam::MatcherOptions{}, 30.0, area::AreaOptions{});
}

Observations observe(const std::vector<testing_sim::Segment>& world,
                                const std::vector<Pose2D>& poses) {
  std::vector<LaserScan> scans;
  for (const Pose2D& p : poses) scans.push_back(scan_at(world, p));
  std::vector<PosedScan> posed;
  for (size_t i = 0; i < poses.size(); ++i) posed.push_back({poses[i], &scans[i]});
  return gather_observations(posed, poses.back(), 20.0, 0.05, 600);
}

TEST(TransitionModel, KnownAreaAgainWinsWhereTheObservationsMatchIt) {
  TwoKnownAreas s;
  const Pose2D truth(3, 3, 0.2);  // in area 1, which is the world frame
  // The robot's belief in area 3, 0.2 m / 0.05 rad off the truth.
  const Pose2D believed = (truth - s.origin3) + Pose2D(0.15, -0.12, 0.05);
  const auto obs = observe(testing_sim::office_world(),
                           {{2.0, 2.8, 0.2}, {2.5, 2.9, 0.2}, truth});
  const auto out = model().evaluate(s.map, 3, PoseGaussian(believed, diag(0.1, 0.05)), obs);
  ASSERT_GE(out.size(), 2u);
  // Both were weighed: "new area" first, then the known areas.
  EXPECT_TRUE(out[0].is_new());
  EXPECT_LT(out[0].probability, 0.01);
  for (size_t i = 1; i < out.size(); ++i) EXPECT_FALSE(out[i].is_new());
  const Outcome* one = nullptr;
  for (const auto& o : out)
    if (o.area == 1) one = &o;
  ASSERT_NE(one, nullptr) << "area 1 must be a candidate";
  EXPECT_GT(one->probability, 0.99);
  EXPECT_GT(one->match_ratio, 0.8);
  // The mode is the true pose in area 1's frame.
  EXPECT_NEAR(one->robot.mean.x, truth.x, 0.03);
  EXPECT_NEAR(one->robot.mean.y, truth.y, 0.03);
  EXPECT_NEAR(one->robot.mean.theta, truth.theta, 0.01);
  EXPECT_TRUE(topology::is_positive_definite(one->robot.cov));
  // The prior came through the arcs: the believed pose, seen from area 1.
  const Pose2D expected_prior = s.origin3 + believed;
  EXPECT_NEAR(one->prior.mean.x, expected_prior.x, 1e-9);
  EXPECT_NEAR(one->prior.mean.y, expected_prior.y, 1e-9);
  double sum = 0;
  for (const auto& o : out) sum += o.probability;
  EXPECT_NEAR(sum, 1.0, 1e-12);
}

TEST(TransitionModel, NewAreaWinsWhenNoKnownMapExplainsTheObservations) {
  TwoKnownAreas s;
  const Pose2D truth(3, 3, 0.2);
  const Pose2D believed = truth - s.origin3;
  // The same prior, but the robot is in a corridor no area has mapped.
  const auto obs = observe(testing_sim::corridor_world(), {{10, 1.5, 0.0}, {10.5, 1.5, 0.0}});
  const auto out = model().evaluate(s.map, 3, PoseGaussian(believed, diag(0.1, 0.05)), obs);
  ASSERT_FALSE(out.empty());
  EXPECT_TRUE(out[0].is_new());
  EXPECT_GT(out[0].probability, 0.99);
}

TEST(TransitionModel, EtaTradesNewAgainstKnown) {
  TwoKnownAreas s;
  const Pose2D truth(3, 3, 0.2);
  const auto obs = observe(testing_sim::office_world(), {truth});
  const PoseGaussian robot(truth - s.origin3, diag(0.1, 0.05));
  const auto known = model(10.0).evaluate(s.map, 3, robot, obs);
  ASSERT_GE(known.size(), 2u);
  const double log_f1 = known[1].log_f;
  // With eta just above F(1) the new area becomes the more probable.
  const auto out = model(log_f1 + 1.0).evaluate(s.map, 3, robot, obs);
  ASSERT_FALSE(out.empty());
  EXPECT_TRUE(out[0].is_new());
  EXPECT_NEAR(out[0].probability, std::exp(1.0) / (1.0 + std::exp(1.0)), 0.01);
}

TEST(TransitionModel, BroaderPriorLowersTheExpectedLikelihood) {
  TwoKnownAreas s;
  const auto world = testing_sim::office_world();
  const Pose2D truth(3, 3, 0.2);
  const auto obs = observe(world, {truth});
  const TransitionModel m = model();
  const auto tight = m.expected_likelihood(*s.map.area(1).map,
                                           PoseGaussian(truth, diag(0.1, 0.05)), obs);
  const auto broad = m.expected_likelihood(*s.map.area(1).map,
                                           PoseGaussian(truth, diag(0.5, 0.2)), obs);
  ASSERT_TRUE(tight.candidate);
  ASSERT_TRUE(broad.candidate);
  // The Occam factor: the same match is worth less under a vaguer prior.
  EXPECT_LT(broad.log_f, tight.log_f - 1.0);
  // A prior far from where the observations fit gates the area out.
  const auto far = m.expected_likelihood(*s.map.area(1).map,
                                         PoseGaussian(Pose2D(3, 3, 2.0), diag(0.05, 0.02)), obs);
  EXPECT_FALSE(far.candidate);
}

TEST(TransitionModel, TheCurrentAreaAndAreasWithoutMapsAreNotCandidates) {
  TwoKnownAreas s;
  const Pose2D truth(14, 5, 0.0);  // in area 2's part of the office
  const auto obs = observe(testing_sim::office_world(), {truth});
  // Standing in area 2 itself: area 2 is not a candidate.
  const auto out = model().evaluate(s.map, 2, PoseGaussian(truth - s.origin2, diag(0.1, 0.05)), obs);
  for (const auto& o : out) EXPECT_NE(o.area, 2u);
  // Area 3 has no map: never a candidate.
  const auto out1 = model().evaluate(s.map, 1, PoseGaussian(truth, diag(0.1, 0.05)), obs);
  for (const auto& o : out1) EXPECT_NE(o.area, 3u);
}

TEST(ProbableOutcomes, KeepsThoseAboveTheThresholdOrTheBest) {
  std::vector<Outcome> o(3);
  o[0].probability = 0.0005;
  o[1].probability = 0.9;
  o[2].probability = 0.0995;
  EXPECT_EQ(probable_outcomes(o, 1e-3), (std::vector<size_t>{1, 2}));
  EXPECT_EQ(probable_outcomes(o, 0.95), (std::vector<size_t>{1}));
}

TEST(Observations, ReExpressedFromTheCurrentPose) {
  LaserScan scan;
  scan.angle_min = 0.0;
  scan.angle_increment = 0.1;
  scan.ranges = {2.0};
  scan.valid = {1};
  scan.max_range = 30.0f;
  const Pose2D earlier(1, 0, 0), now(0, 0, M_PI / 2);
  const auto pts = gather_observations({{earlier, &scan}}, now, 20.0, 0.05, 100).points;
  ASSERT_EQ(pts.hit.size(), 1u);
  // The end point (3, 0) in the common frame, seen from `now` facing +y.
  EXPECT_NEAR(pts.hit[0].x, 0.0, 1e-9);
  EXPECT_NEAR(pts.hit[0].y, -3.0, 1e-9);
}

}  // namespace
}  // namespace hmt::tsbi
