#include "hmt/tsbi/transition_model.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>

#include <cmath>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "hmt/topology/shortest_paths.h"
#include "test_maps.h"

namespace hmt::tsbi {
namespace {

using topology::AreaId;
using topology::HmtMap;
using topology::PoseGaussian;
using test_maps::diag;
using test_maps::map_of;
using test_maps::observe;

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

TransitionModel model(double log_eta = 10.0, int bound_boxes = TsbiOptions{}.bound_boxes,
                      std::shared_ptr<WorkerPool> pool = nullptr) {
  TsbiOptions o;
  o.log_eta = log_eta;
  o.bound_boxes = bound_boxes;
  return TransitionModel(o, metric_slam::MatcherOptions{}, 30.0, area::AreaOptions{},
                         std::move(pool));
}

// The outcomes agree in every field the hybrid filter uses.
void expect_same_outcomes(const std::vector<Outcome>& a, const std::vector<Outcome>& b) {
  ASSERT_EQ(a.size(), b.size());
  for (size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].area, b[i].area);
    EXPECT_EQ(a[i].log_f, b[i].log_f);
    EXPECT_EQ(a[i].probability, b[i].probability);
    EXPECT_EQ(a[i].robot.mean.x, b[i].robot.mean.x);
    EXPECT_EQ(a[i].robot.mean.theta, b[i].robot.mean.theta);
    EXPECT_EQ(a[i].robot.cov, b[i].robot.cov);
    EXPECT_EQ(a[i].modes, b[i].modes);
  }
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

// A corridor mapped from x = 2-10 with an 8 m laser, so that its map ends
// near x = 18, seen again from near that end with a longer laser.
struct CorridorEnd {
  std::vector<testing_sim::Segment> world = testing_sim::corridor_world(60.0);
  std::shared_ptr<grid::OccupancyGrid> map = std::make_shared<grid::OccupancyGrid>(0.05);
  CorridorEnd() {
    for (double x = 2; x <= 10; x += 1) {
      const Pose2D p(x, 1.5, 0);
      grid::insert_scan(*map, p, testing_sim::cast_scan(world, p, 361, M_PI, 8.0, nullptr, 0.0),
                        grid::InsertionOptions{});
    }
  }
  // The evaluation of this area with the robot at (x, 1.5, 0), after scans
  // 2 and 1 m back, under a prior 0.1 m / 0.02 rad off.
  ExpectedLikelihood at(double x) const {
    const Pose2D truth(x, 1.5, 0);
    const auto obs = observe(world, {{x - 2, 1.5, 0}, {x - 1, 1.5, 0}, truth});
    return model().expected_likelihood(*map, PoseGaussian(truth + Pose2D(0.1, -0.05, 0.02),
                                                          diag(0.1, 0.05)), obs);
  }
};

TEST(TransitionModel, AReturnAtAnAreasEdgeIsJudgedOnThePointsWithinItsExtent) {
  CorridorEnd c;
  // From x = 15, near half the points lie beyond the map: fewer than
  // min_match_ratio of all of them are explained, but nearly all of those
  // within the map's extent are. The area is a candidate, at the true pose.
  const ExpectedLikelihood edge = c.at(15.0);
  ASSERT_TRUE(edge.candidate);
  EXPECT_LT(edge.match_ratio, TsbiOptions{}.min_match_ratio);
  EXPECT_GE(edge.match_ratio, TsbiOptions{}.min_points_explained);
  EXPECT_NEAR(edge.robot.mean.y, 1.5, 0.03);
  EXPECT_NEAR(edge.robot.mean.theta, 0.0, 0.01);
  // Required to explain min_match_ratio of all the points, it is not.
  TsbiOptions all;
  all.log_eta = 10.0;
  all.min_points_explained = all.min_match_ratio;
  const TransitionModel strict(all, metric_slam::MatcherOptions{}, 30.0, area::AreaOptions{});
  const Pose2D truth(15, 1.5, 0);
  const auto obs = test_maps::observe(c.world, {{13, 1.5, 0}, {14, 1.5, 0}, truth});
  EXPECT_FALSE(strict.expected_likelihood(*c.map, PoseGaussian(truth + Pose2D(0.1, -0.05, 0.02),
                                                               diag(0.1, 0.05)), obs)
                   .candidate);
  // Two metres further out, what it can explain is under
  // min_points_explained of the points: too little overlap to judge on.
  EXPECT_FALSE(c.at(17.0).candidate);
}

// A room mapped from all around, and seen again from the same path with
// something standing on the floor the map saw open.
struct RoomSeenAgain {
  std::vector<testing_sim::Segment> room = testing_sim::office_world();
  std::shared_ptr<const grid::OccupancyGrid> map =
      map_of(room, Pose2D(), {{2, 2, 0}, {4, 4, 1.5}, {6, 8, 3.0}, {2, 8, -1.5}, {5, 3, 0.5},
                              {3, 6, -0.5}, {6, 5, 2.5}});
  Pose2D truth{3, 3, 0.2};
  std::vector<Pose2D> path = {{2.0, 2.8, 0.2}, {2.5, 2.9, 0.2}, truth};
  PoseGaussian prior{truth + Pose2D(0.1, -0.05, 0.02), diag(0.1, 0.05)};
  ExpectedLikelihood seen(const std::vector<testing_sim::Segment>& world, double limit) const {
    TsbiOptions o;
    o.log_eta = 10.0;
    o.max_points_contradicted = limit;
    return TransitionModel(o, metric_slam::MatcherOptions{}, 30.0, area::AreaOptions{})
        .expected_likelihood(*map, prior, observe(world, path));
  }
};

// A partition standing there: the return matches the room's other walls,
// but the partition's points land where the map saw through. That is
// another room, not this one.
TEST(TransitionModel, AMatchWhosePointsLieInTheMapsFreeSpaceIsNoMode) {
  const RoomSeenAgain r;
  auto partitioned = r.room;
  partitioned.push_back({3.0, 5.0, 7.5, 5.0});
  // Without the limit the other walls make a match, at the true pose.
  const ExpectedLikelihood loose = r.seen(partitioned, 1.0);
  ASSERT_TRUE(loose.candidate);
  EXPECT_NEAR(loose.robot.mean.x, r.truth.x, 0.05);
  EXPECT_NEAR(loose.robot.mean.y, r.truth.y, 0.05);
  // With the default limit the partition rules the room out...
  EXPECT_FALSE(r.seen(partitioned, TsbiOptions{}.max_points_contradicted).candidate);
  // ... and the room as it was mapped is matched.
  EXPECT_TRUE(r.seen(r.room, TsbiOptions{}.max_points_contradicted).candidate);
}

// People standing there instead: as many returns land on the open floor as
// on the partition, but each person is a short surface (0.4 m), not a wall
// the map saw through. The room is matched.
TEST(TransitionModel, PeopleOnTheMapsOpenFloorDoNotRuleTheAreaOut) {
  const RoomSeenAgain r;
  auto crowded = r.room;
  for (const double x : {3.2, 4.1, 5.0, 5.9, 6.8}) {  // five people, 0.9 m apart
    crowded.push_back({x, 5.0, x + 0.4, 5.0});
    crowded.push_back({x + 0.4, 5.0, x + 0.4, 5.3});
  }
  const ExpectedLikelihood e = r.seen(crowded, TsbiOptions{}.max_points_contradicted);
  ASSERT_TRUE(e.candidate);
  EXPECT_NEAR(e.robot.mean.x, r.truth.x, 0.05);
  EXPECT_NEAR(e.robot.mean.y, r.truth.y, 0.05);
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

// A known area whose F is below min_probability x eta would be less
// probable than min_probability against the unexplored area alone: it
// could never get a hypothesis, so it is no outcome (and is not checked).
TEST(TransitionModel, AnAreaBelowMinProbabilityAgainstEtaAloneIsNoOutcome) {
  TwoKnownAreas s;
  const Pose2D truth(3, 3, 0.2);
  const auto obs = observe(testing_sim::office_world(), {truth});
  const PoseGaussian robot(truth - s.origin3, diag(0.1, 0.05));
  auto f_of_area_1 = [](const std::vector<Outcome>& out) {
    for (const Outcome& o : out)
      if (o.area == 1) return o.log_f;
    return -HUGE_VAL;
  };
  const double log_f1 = f_of_area_1(model(10.0).evaluate(s.map, 3, robot, obs));
  ASSERT_GT(log_f1, -HUGE_VAL) << "area 1 must be a candidate";
  const double edge = log_f1 - std::log(TsbiOptions{}.min_probability);  // log eta at the edge
  EXPECT_EQ(f_of_area_1(model(edge - 0.1).evaluate(s.map, 3, robot, obs)), log_f1);
  EXPECT_EQ(f_of_area_1(model(edge + 0.1).evaluate(s.map, 3, robot, obs)), -HUGE_VAL);
}

// The arcs 1-2 and 2-3 as fine alignments leave them: millimetres and a
// milliradian, 1-2's heading 0.1 rad off. Dijkstra from area 3 prefers them
// to a direct arc 1-3 of 5 cm and 0.02 rad that has it right.
struct ContradictoryLoop : TwoKnownAreas {
  explicit ContradictoryLoop(bool direct_arc) {
    const Pose2D off(origin2.x, origin2.y, origin2.theta + 0.1);
    map.set_arc({1, 2, PoseGaussian(off, diag(0.002, 0.001)), 1});
    map.set_arc({2, 3, PoseGaussian(origin3 - origin2, diag(0.002, 0.001)), 1});
    if (direct_arc) map.add_arc_measurement(1, 3, PoseGaussian(origin3, diag(0.05, 0.02)));
  }
};

TEST(TransitionModel, APathThatContradictsTheAreasOwnArcStillFindsTheArea) {
  const Pose2D truth(3, 3, 0.2);
  const auto obs = observe(testing_sim::office_world(), {{2.0, 2.8, 0.2}, {2.5, 2.9, 0.2}, truth});
  auto area_1 = [&](const ContradictoryLoop& s) {
    const PoseGaussian robot(truth - s.origin3, diag(0.02, 0.005));
    for (const Outcome& o : model().evaluate(s.map, 3, robot, obs))
      if (o.area == 1) return std::optional<Outcome>(o);
    return std::optional<Outcome>();
  };
  // Without the direct arc, the prior through area 2 places the robot
  // 0.67 m and 0.1 rad off, and area 1 is missed.
  const ContradictoryLoop path_only(false);
  ASSERT_EQ(topology::shortest_paths(path_only.map, 3).path_to(1),
            (std::vector<AreaId>{3, 2, 1}));
  EXPECT_FALSE(area_1(path_only));
  // With it, Dijkstra still takes the way through area 2, but the prior is
  // widened to hold the direct arc too, and the return is found.
  const ContradictoryLoop both(true);
  const topology::PathTree tree = topology::shortest_paths(both.map, 3);
  ASSERT_EQ(tree.path_to(1), (std::vector<AreaId>{3, 2, 1}));
  const std::optional<Outcome> found = area_1(both);
  ASSERT_TRUE(found) << "area 1 must be a candidate";
  EXPECT_GT(found->probability, 0.99);
  EXPECT_NEAR(found->robot.mean.x, truth.x, 0.03);
  EXPECT_NEAR(found->robot.mean.y, truth.y, 0.03);
  EXPECT_NEAR(found->robot.mean.theta, truth.theta, 0.01);
}

TEST(CandidateFrame, IsDijkstrasPoseUnlessThePathContradictsTheAreasOwnArc) {
  const TsbiOptions o;
  const ContradictoryLoop s(true);
  const topology::PathTree tree = topology::shortest_paths(s.map, 3);
  const PoseGaussian path = tree.pose_of(1);
  const PoseGaussian direct = s.map.arc(3, 1);
  // Widened by the disagreement, about the path's mean.
  const PoseGaussian widened = candidate_frame(s.map, tree, 3, 1, o);
  const Eigen::Vector3d d = topology::difference(direct.mean, path.mean);
  EXPECT_EQ(widened.mean.x, path.mean.x);
  EXPECT_EQ(widened.mean.y, path.mean.y);
  EXPECT_EQ(widened.mean.theta, path.mean.theta);
  EXPECT_TRUE(widened.cov.isApprox(path.cov + d * d.transpose(), 1e-12));
  // Dijkstra's pose, bit for bit: where the path is the two areas' own arc
  // (area 3 seen from area 2), where they share none (no arc 1-3), and
  // where their arc agrees with the path (5 cm off, inside the gate).
  const topology::PathTree from2 = topology::shortest_paths(s.map, 2);
  EXPECT_EQ(candidate_frame(s.map, from2, 2, 3, o).cov, from2.pose_of(3).cov);
  const ContradictoryLoop no_direct(false);
  const topology::PathTree tree2 = topology::shortest_paths(no_direct.map, 3);
  EXPECT_EQ(candidate_frame(no_direct.map, tree2, 3, 1, o).cov, tree2.pose_of(1).cov);
  ContradictoryLoop agreeing(false);
  agreeing.map.add_arc_measurement(
      1, 3, PoseGaussian(topology::compose_path(agreeing.map, {1, 2, 3}).mean + Pose2D(0.05, 0, 0),
                         diag(0.05, 0.02)));
  const topology::PathTree tree3 = topology::shortest_paths(agreeing.map, 3);
  ASSERT_EQ(tree3.path_to(1), (std::vector<AreaId>{3, 2, 1}));
  EXPECT_EQ(candidate_frame(agreeing.map, tree3, 3, 1, o).cov, tree3.pose_of(1).cov);
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

TEST(TransitionModel, ReturnsOfOneSurfaceAddNoEvidence) {
  // The same scan twice is no more evidence than once when the evidence is
  // the cells the returns hit; counted return by return it is twice as much.
  TwoKnownAreas s;
  const auto world = testing_sim::office_world();
  const Pose2D truth(3, 3, 0.2);
  const PoseGaussian prior(truth, diag(0.3, 0.1));
  const TransitionModel m = model();
  const auto& map = *s.map.area(1).map;
  const auto once = m.expected_likelihood(map, prior, observe(world, {truth}, 0.25));
  const auto twice = m.expected_likelihood(map, prior, observe(world, {truth, truth}, 0.25));
  ASSERT_TRUE(once.candidate);
  ASSERT_TRUE(twice.candidate);
  EXPECT_NEAR(twice.log_f, once.log_f, 0.05 * std::fabs(once.log_f));
  const auto once_each = m.expected_likelihood(map, prior, observe(world, {truth}));
  const auto twice_each = m.expected_likelihood(map, prior, observe(world, {truth, truth}));
  ASSERT_TRUE(once_each.candidate);
  ASSERT_TRUE(twice_each.candidate);
  EXPECT_GT(twice_each.log_f, once_each.log_f + 0.5 * std::fabs(once_each.log_f));
  // The weighting follows how the observations were gathered, whatever the
  // model's own evidence_cell (which only says how to gather them).
  TsbiOptions o;
  o.log_eta = 10.0;
  o.evidence_cell = 0.0;
  const TransitionModel per_return(o, metric_slam::MatcherOptions{}, 30.0, area::AreaOptions{});
  EXPECT_EQ(per_return.expected_likelihood(map, prior, observe(world, {truth}, 0.25)).log_f,
            once.log_f);
  EXPECT_EQ(per_return.expected_likelihood(map, prior, observe(world, {truth})).log_f,
            once_each.log_f);
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

// A scene where area 1 explains the observations (under a broad prior, so
// the wide search runs too) and area 2, elsewhere in the office, cannot.
struct ReturnToAreaOne {
  TwoKnownAreas s;
  Observations obs =
      observe(testing_sim::office_world(), {{2.0, 2.8, 0.2}, {2.5, 2.9, 0.2}, {3, 3, 0.2}});
  PoseGaussian robot{(Pose2D(3, 3, 0.2) - s.origin3) + Pose2D(0.3, -0.2, 0.08),
                     diag(0.4, 0.12)};
};

TEST(TransitionModel, SkippingHopelessAreasChangesNoOutcome) {
  ReturnToAreaOne r;
  const auto full = model(10.0, 0).evaluate(r.s.map, 3, r.robot, r.obs);
  const auto pruned = model(10.0).evaluate(r.s.map, 3, r.robot, r.obs);
  ASSERT_GE(full.size(), 2u);
  EXPECT_EQ(full[1].area, 1u);
  expect_same_outcomes(full, pruned);
  // Observations from a corridor nothing mapped: both find no candidate.
  const auto corridor = observe(testing_sim::corridor_world(), {{10, 1.5, 0.0}, {10.5, 1.5, 0.0}});
  EXPECT_EQ(model(10.0, 0).evaluate(r.s.map, 3, r.robot, corridor).size(), 1u);
  EXPECT_EQ(model(10.0).evaluate(r.s.map, 3, r.robot, corridor).size(), 1u);
}

// The report of an event: every known area the arcs reach, once, in
// ascending id, with the verdict that matches what evaluate() returned;
// asking for it changes no outcome.
TEST(TransitionModel, ReportsWhatBecameOfEveryKnownArea) {
  ReturnToAreaOne r;
  const auto plain = model().evaluate(r.s.map, 3, r.robot, r.obs);
  std::vector<CandidateReport> considered;
  const auto out = model().evaluate(r.s.map, 3, r.robot, r.obs, &considered);
  expect_same_outcomes(plain, out);
  ASSERT_EQ(considered.size(), 2u);  // areas 1 and 2 (3 is the current one)
  EXPECT_EQ(considered[0].area, 1u);
  EXPECT_EQ(considered[1].area, 2u);
  // Area 1 is the outcome: its report carries the outcome's F and prior.
  ASSERT_GE(out.size(), 2u);
  EXPECT_EQ(out[1].area, 1u);
  EXPECT_EQ(considered[0].verdict, CandidateReport::Verdict::kOutcome);
  EXPECT_EQ(considered[0].log_f, out[1].log_f);
  EXPECT_EQ(considered[0].prior_mean.x, out[1].prior.mean.x);
  EXPECT_EQ(considered[0].prior_sd(2), std::sqrt(out[1].prior.cov(2, 2)));
  EXPECT_TRUE(considered[0].wide);  // the broad prior was searched as a whole
  EXPECT_GT(considered[0].starts, 27u);
  EXPECT_GE(considered[0].best_ratio, out[1].match_ratio);
  // Area 2, elsewhere in the office, explains too little: it is no outcome,
  // and its report says why.
  for (const Outcome& o : out) EXPECT_NE(o.area, 2u);
  EXPECT_NE(considered[1].verdict, CandidateReport::Verdict::kOutcome);
  EXPECT_LT(considered[1].best_ratio, TsbiOptions{}.min_match_ratio);
  // Observations from a corridor nothing mapped: neither area is an outcome,
  // both are still reported.
  const auto corridor = observe(testing_sim::corridor_world(), {{10, 1.5, 0.0}, {10.5, 1.5, 0.0}});
  const auto none = model().evaluate(r.s.map, 3, r.robot, corridor, &considered);
  EXPECT_EQ(none.size(), 1u);
  ASSERT_EQ(considered.size(), 2u);
  for (const CandidateReport& c : considered)
    EXPECT_NE(c.verdict, CandidateReport::Verdict::kOutcome) << "area " << c.area;
}

// The verdicts' names, as tsbi_candidates.csv writes them.
TEST(CandidateReport, VerdictsHaveDistinctNames) {
  using V = CandidateReport::Verdict;
  const std::vector<V> all = {V::kOutOfReach, V::kBound, V::kImprobable,
                              V::kNoMode,     V::kAreaCheck, V::kOutcome};
  std::set<std::string> names;
  for (V v : all) names.insert(verdict_name(v));
  EXPECT_EQ(names.size(), all.size());
  EXPECT_EQ(std::string(verdict_name(V::kOutcome)), "outcome");
}

// An area whose map no observation can reach from the prior's gate is
// reported out of reach and never searched.
TEST(TransitionModel, ReportsAnAreaBeyondReachAsOutOfReach) {
  TwoKnownAreas s;
  // Area 1's map drawn 200 m from where its arcs put it: the arcs still
  // reach the area, the observations (an office's few metres) cannot.
  s.map.set_map(1, map_of(testing_sim::office_world(), Pose2D(-200, 0, 0), {{2, 2, 0}}));
  const Pose2D truth(14, 5, 0.0);
  const auto obs = observe(testing_sim::office_world(), {truth});
  std::vector<CandidateReport> considered;
  model().evaluate(s.map, 3, PoseGaussian(truth - s.origin3, diag(0.1, 0.05)), obs, &considered);
  ASSERT_EQ(considered.size(), 2u);
  EXPECT_EQ(considered[0].area, 1u);
  EXPECT_EQ(considered[0].verdict, CandidateReport::Verdict::kOutOfReach);
  EXPECT_EQ(considered[0].starts, 0u);
}

// Rival hypotheses at one event: their queries weighed together give each
// the outcomes and the reports it gets alone, to the bit, whatever the
// threads. Here: the return to area 1 under a broad prior, the same
// observations under another hypothesis's map (area 1 drawn elsewhere, so
// out of reach) and prior, and observations nothing mapped.
TEST(TransitionModel, AnEventsHypothesesWeighedTogetherGetWhatEachGetsAlone) {
  ReturnToAreaOne r;
  HmtMap other = r.s.map;
  other.set_map(1, map_of(testing_sim::office_world(), Pose2D(-200, 0, 0), {{2, 2, 0}}));
  const PoseGaussian narrow((Pose2D(3, 3, 0.2) - r.s.origin3) + Pose2D(0.1, 0.05, 0.02),
                            diag(0.1, 0.05));
  const auto corridor = observe(testing_sim::corridor_world(), {{10, 1.5, 0.0}, {10.5, 1.5, 0.0}});
  const std::vector<TransitionModel::Query> queries = {
      {&r.s.map, 3, r.robot, &r.obs},
      {&other, 3, narrow, &r.obs},
      {&r.s.map, 3, narrow, &r.obs},
      {&r.s.map, 3, r.robot, &corridor}};
  for (int threads : {1, 3}) {
    auto pool = threads > 1 ? std::make_shared<WorkerPool>(threads) : nullptr;
    TransitionModel together = model(10.0, TsbiOptions{}.bound_boxes, pool);
    std::vector<std::vector<CandidateReport>> reports;
    const auto all = together.evaluate_all(queries, &reports);
    ASSERT_EQ(all.size(), queries.size());
    ASSERT_EQ(reports.size(), queries.size());
    for (size_t q = 0; q < queries.size(); ++q) {
      SCOPED_TRACE("query " + std::to_string(q) + ", threads " + std::to_string(threads));
      std::vector<CandidateReport> alone_reports;
      const auto alone = model().evaluate(*queries[q].map, queries[q].current, queries[q].robot,
                                          *queries[q].observations, &alone_reports);
      expect_same_outcomes(alone, all[q]);
      ASSERT_EQ(alone_reports.size(), reports[q].size());
      for (size_t k = 0; k < alone_reports.size(); ++k) {
        EXPECT_EQ(alone_reports[k].area, reports[q][k].area);
        EXPECT_EQ(alone_reports[k].verdict, reports[q][k].verdict);
        EXPECT_EQ(alone_reports[k].starts, reports[q][k].starts);
        EXPECT_EQ(alone_reports[k].best_ratio, reports[q][k].best_ratio);
        EXPECT_EQ(alone_reports[k].log_f, reports[q][k].log_f);
      }
    }
    // The queries differ, so the test is not of four copies of one answer:
    // the return is found under its own map, not where area 1 is drawn
    // 200 m away, nor from the corridor.
    ASSERT_GE(all[0].size(), 2u);
    EXPECT_EQ(all[0][1].area, 1u);
    EXPECT_EQ(reports[1][0].verdict, CandidateReport::Verdict::kOutOfReach);
    EXPECT_EQ(all[3].size(), 1u);
  }
}

TEST(TransitionModel, SameOutcomesWhateverTheThreads) {
  ReturnToAreaOne r;
  const auto alone = model().evaluate(r.s.map, 3, r.robot, r.obs);
  const auto pooled = model(10.0, TsbiOptions{}.bound_boxes,
                            std::make_shared<WorkerPool>(3))
                          .evaluate(r.s.map, 3, r.robot, r.obs);
  ASSERT_GE(alone.size(), 2u);
  expect_same_outcomes(alone, pooled);
}

TEST(TransitionModel, KeepsTheMatchFieldsOfHeldMapsOnly) {
  ReturnToAreaOne r;
  TransitionModel m = model();
  const auto first = m.evaluate(r.s.map, 3, r.robot, r.obs);
  EXPECT_EQ(m.cached_fields(), 2u);  // areas 1 and 2
  // Reused: the same outcomes from the cached fields.
  expect_same_outcomes(first, m.evaluate(r.s.map, 3, r.robot, r.obs));
  // Area 2's map replaced (as when it is archived again): its old field goes.
  r.s.map.set_map(2, map_of(testing_sim::office_world(), r.s.origin2, {{12, 3, 0}}));
  m.evaluate(r.s.map, 3, r.robot, r.obs);
  EXPECT_EQ(m.cached_fields(), 2u);
  {
    HmtMap other = r.s.map;  // shares both maps
    other.set_map(1, map_of(testing_sim::office_world(), Pose2D(), {{2, 2, 0}}));
    m.evaluate(other, 3, r.robot, r.obs);
    EXPECT_EQ(m.cached_fields(), 3u);  // area 1's two maps are both held
  }
  m.evaluate(r.s.map, 3, r.robot, r.obs);
  EXPECT_EQ(m.cached_fields(), 2u);  // `other`'s map of area 1 died with it
}

// A return after a long loop: the prior is wide (3 m, 0.4 rad) and the true
// pose lies far from its mean, away from every matcher start. The lattice,
// coarsened to its 50000 poses (0.65 m / 0.09 rad steps), finds no pose
// close enough for the matcher to converge: the closure is missed. The
// branch and bound scores every pose of its 0.05 m / 0.01 rad lattice in
// the gate, and the best is the truth.
TEST(TransitionModel, WideSearchFindsAFarReturnTheCoarseLatticeMisses) {
  TwoKnownAreas s;
  const auto world = testing_sim::office_world();
  const Pose2D truth(3, 3, 0.2);
  const auto obs = observe(world, {{2.5, 2.9, 0.2}, truth});
  const PoseGaussian prior(truth + Pose2D(4.5, -2.0, 0.55), diag(3.0, 0.4));
  const Eigen::Vector3d e = topology::difference(truth, prior.mean);
  ASSERT_LT(e.dot(prior.cov.inverse() * e), TsbiOptions{}.gate);  // the truth is in the gate
  auto with = [&](TsbiOptions::WideSearch search) {
    TsbiOptions o;
    o.search = search;
    return TransitionModel(o, metric_slam::MatcherOptions{}, 30.0, area::AreaOptions{})
        .expected_likelihood(*s.map.area(1).map, prior, obs);
  };
  auto found = [&](const ExpectedLikelihood& f) {
    return f.candidate && std::hypot(f.robot.mean.x - truth.x, f.robot.mean.y - truth.y) < 0.05 &&
           std::fabs(wrap_angle(f.robot.mean.theta - truth.theta)) < 0.02;
  };
  EXPECT_FALSE(found(with(TsbiOptions::WideSearch::kLattice)));
  const ExpectedLikelihood bnb = with(TsbiOptions::WideSearch::kBnb);
  EXPECT_TRUE(found(bnb));
  EXPECT_GT(bnb.match_ratio, 0.8);
}

// The cost stacks are a cache: with no budget for them (each rebuilt at
// every event) the outcomes are the same, and the stacks an event did not
// use are not kept.
TEST(TransitionModel, SameOutcomesWhateverTheStackBudget) {
  ReturnToAreaOne r;
  TsbiOptions none;
  none.log_eta = 10.0;
  none.bnb_cache_mb = 0;
  TransitionModel unbudgeted = model();
  TransitionModel budgetless(none, metric_slam::MatcherOptions{}, 30.0, area::AreaOptions{});
  const auto a = unbudgeted.evaluate(r.s.map, 3, r.robot, r.obs);
  ASSERT_GE(a.size(), 2u);
  EXPECT_GE(unbudgeted.cached_stacks(), 1u);  // the prior is wide: the search ran
  expect_same_outcomes(a, budgetless.evaluate(r.s.map, 3, r.robot, r.obs));
  expect_same_outcomes(a, budgetless.evaluate(r.s.map, 3, r.robot, r.obs));
  // Threads build, share and evict the stacks as they search (the cache
  // is locked): the same outcomes, with or without a budget.
  for (int mb : {0, TsbiOptions{}.bnb_cache_mb}) {
    TsbiOptions o = none;
    o.bnb_cache_mb = mb;
    TransitionModel pooled(o, metric_slam::MatcherOptions{}, 30.0, area::AreaOptions{},
                           std::make_shared<WorkerPool>(3));
    expect_same_outcomes(a, pooled.evaluate(r.s.map, 3, r.robot, r.obs));
    expect_same_outcomes(a, pooled.evaluate(r.s.map, 3, r.robot, r.obs));
  }
  // An event whose prior is narrow uses no stack: the budgetless model
  // drops the ones it held.
  budgetless.evaluate(r.s.map, 3, PoseGaussian(r.robot.mean, diag(0.05, 0.01)), r.obs);
  EXPECT_EQ(budgetless.cached_stacks(), 0u);
  EXPECT_EQ(budgetless.cached_stack_bytes(), 0u);
}

// The match fields too: with no budget each event rebuilds the fields it
// needs and keeps only those, and the outcomes do not change.
TEST(TransitionModel, SameOutcomesWhateverTheFieldBudget) {
  ReturnToAreaOne r;
  TsbiOptions none;
  none.log_eta = 10.0;
  none.field_cache_mb = 0;
  TransitionModel unbudgeted = model();
  TransitionModel budgetless(none, metric_slam::MatcherOptions{}, 30.0, area::AreaOptions{});
  const auto a = unbudgeted.evaluate(r.s.map, 3, r.robot, r.obs);
  ASSERT_GE(a.size(), 2u);
  const size_t fields = unbudgeted.cached_fields();
  EXPECT_GE(fields, 1u);
  EXPECT_GT(unbudgeted.cached_field_bytes(), 0u);
  expect_same_outcomes(a, budgetless.evaluate(r.s.map, 3, r.robot, r.obs));
  expect_same_outcomes(a, budgetless.evaluate(r.s.map, 3, r.robot, r.obs));
  // Only the fields of the last event stay, however small the budget.
  EXPECT_LE(budgetless.cached_fields(), fields);
  expect_same_outcomes(a, unbudgeted.evaluate(r.s.map, 3, r.robot, r.obs));
}

TEST(ProbableOutcomes, KeepsThoseAboveTheThresholdOrTheBest) {
  std::vector<Outcome> o(3);
  o[0].probability = 0.0005;
  o[1].probability = 0.9;
  o[2].probability = 0.0995;
  EXPECT_EQ(probable_outcomes(o, 1e-3), (std::vector<size_t>{1, 2}));
  EXPECT_EQ(probable_outcomes(o, 0.95), (std::vector<size_t>{1}));
}

TEST(LogEvidence, SumsTheOutcomesFAgainstEta) {
  std::vector<Outcome> o(1);
  o[0].log_f = 8.0;  // "new" alone: no evidence either way
  EXPECT_DOUBLE_EQ(log_evidence(o, 8.0), 0.0);
  o.resize(3);
  o[1].area = 3;
  o[1].log_f = 8.0;
  o[2].area = 5;
  o[2].log_f = 20.0;
  // log(e^8 + e^8 + e^20) - 8, computed without overflow.
  EXPECT_NEAR(log_evidence(o, 8.0), 12.0 + std::log1p(2.0 * std::exp(-12.0)), 1e-12);
  EXPECT_DOUBLE_EQ(log_evidence({}, 8.0), 0.0);
}

// A scan of the given ranges (0: no return) from `angle_min`, `increment` apart.
LaserScan fan(double angle_min, double increment, const std::vector<float>& ranges) {
  LaserScan scan;
  scan.angle_min = angle_min;
  scan.angle_increment = increment;
  scan.ranges = ranges;
  scan.valid.assign(ranges.size(), 1);
  scan.max_range = 30.0f;
  return scan;
}

TEST(Observations, ReExpressedFromTheCurrentPose) {
  const LaserScan scan = fan(0.0, 0.1, {2.0});
  const Pose2D earlier(1, 0, 0), now(0, 0, M_PI / 2);
  const auto pts = gather_observations({{earlier, &scan}}, now, 20.0, 0.05, 100).points;
  ASSERT_EQ(pts.hit.size(), 1u);
  // The end point (3, 0) in the common frame, seen from `now` facing +y.
  EXPECT_NEAR(pts.hit[0].x, 0.0, 1e-9);
  EXPECT_NEAR(pts.hit[0].y, -3.0, 1e-9);
}

TEST(Observations, CountTheDistinctCellsTheReturnsFallIn) {
  // Three returns 2 mm apart on one wall (a fourth beam gave none) and one
  // 1 m away: two 0.25 m cells, however many times the scan is taken.
  const LaserScan scan = fan(0.0, 0.001, {2.1, 2.1, 2.1, 0.0});
  const LaserScan other = fan(0.5, 0.1, {2.0});
  const Pose2D now;
  const auto one = gather_observations({{now, &scan}, {now, &other}}, now, 20.0, 0.05, 100, 0.25);
  EXPECT_EQ(one.points.hit.size(), 4u);
  EXPECT_EQ(one.surface_cells, 2u);
  EXPECT_EQ(one.evidence_cell, 0.25);
  const auto two = gather_observations({{now, &scan}, {now, &other}, {now, &scan}}, now, 20.0,
                                       0.05, 100, 0.25);
  EXPECT_EQ(two.points.hit.size(), 7u);
  EXPECT_EQ(two.surface_cells, 2u);
  // Not counted unless asked.
  const auto uncounted = gather_observations({{now, &scan}}, now, 20.0, 0.05, 100);
  EXPECT_EQ(uncounted.surface_cells, 0u);
  EXPECT_EQ(uncounted.evidence_cell, 0.0);
}

}  // namespace
}  // namespace hmt::tsbi
