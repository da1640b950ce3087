#include "hmt/global_map/keyframe_graph.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "hmt/common/random.h"
#include "hmt/global_map/keyframe_map.h"
#include "hmt/grid/scan_insertion.h"
#include "hmt/sim/ray_world.h"

namespace hmt::global_map {
namespace {

using topology::HmtMap;
using topology::PoseGaussian;

Eigen::Matrix3d diag(double sxy, double st) {
  return Eigen::Vector3d(sxy * sxy, sxy * sxy, st * st).asDiagonal();
}

// A 20 x 10 m office with an inner wall and a few boxes, so that scans pin
// the pose down in every direction.
sim::World office() {
  sim::World w;
  w.box(0, 0, 20, 10);
  w.wall(8, 0, 8, 6);
  w.wall(8, 6, 9, 6);
  w.wall(9, 6, 9, 0);
  w.box(3, 7, 3.8, 7.8);
  w.box(14, 2, 15.2, 3.2);
  w.box(16.5, 7.5, 17.1, 8.1);
  w.box(11, 8, 11.5, 8.5);
  return w;
}

// The robot's true poses along the way-points, 0.1 m a step, heading along
// each leg.
std::vector<Pose2D> drive(const std::vector<Point2D>& waypoints) {
  std::vector<Pose2D> out;
  for (size_t i = 0; i + 1 < waypoints.size(); ++i) {
    const Point2D a = waypoints[i], b = waypoints[i + 1];
    const double len = std::hypot(b.x - a.x, b.y - a.y);
    const double heading = std::atan2(b.y - a.y, b.x - a.x);
    const int n = static_cast<int>(std::round(len / 0.1));
    for (int k = 0; k < n; ++k) {
      const double f = static_cast<double>(k) / n;
      out.emplace_back(a.x + f * (b.x - a.x), a.y + f * (b.y - a.y), heading);
    }
  }
  return out;
}

// A run as the filter would leave it: the office mapped as two areas, the
// robot in area 1 (the root, the world frame), then area 2 (whose frame is
// the robot's pose where it entered), then area 1 again; each area's grid
// built from its own visits' scans at their poses in its frame. The HMT
// map's only arc 1 -> 2 is wrong by `arc_error` with covariance `arc_cov`,
// so the area-grain estimate misplaces area 2 by that much.
struct Scenario {
  std::vector<Pose2D> truth;  // per step, world frame
  Pose2D area2;               // area 2's true frame
  Log log;
  HmtMap map;
  std::vector<AreaVisit> visits;

  // `revisit_error`: the filter's poses of the second visit to area 1 are
  // off by this (composed on the left in area 1's frame: a misplaced
  // re-entry), and that visit's scans are not in area 1's grid.
  // `jitter_xy`, `jitter_theta`: every pose of the filter's path is also off
  // by its own draw of this standard deviation, as a particle's sampled
  // poses are, and the grids are built at those poses.
  Scenario(const Pose2D& arc_error, const Eigen::Matrix3d& arc_cov,
           const Pose2D& revisit_error = Pose2D(), double jitter_xy = 0.0,
           double jitter_theta = 0.0) {
    truth = drive({{1.5, 2}, {6, 2}, {6, 8.5}, {13, 7}, {13, 4.5}, {18, 5}, {18, 8.8},
                   {12.5, 6.5}, {6.5, 8.8}, {6.5, 3}});
    const sim::World world = office();
    sim::Sensor sensor;
    sensor.beams = 360;
    sensor.max_range = 30.0;
    Random noise(7);
    for (size_t i = 0; i < truth.size(); ++i) {
      LogStep s;
      s.timestamp = 0.1 * static_cast<double>(i);
      s.has_odometry = i > 0;
      if (i > 0) s.odometry_increment = truth[i] - truth[i - 1];
      s.scan = sim::raycast(world, truth[i], sensor, &noise, 0.01);
      s.scan.timestamp = s.timestamp;
      log.steps.push_back(std::move(s));
    }
    // Area 2 from the step reaching (10, ~7.3) to the step back at x ~ 11.
    size_t enter = 0, leave = 0;
    for (size_t i = 0; i < truth.size(); ++i) {
      if (!enter && truth[i].x >= 10.0 && truth[i].y > 6.0) enter = i;
      if (enter && i > enter + 100 && !leave && truth[i].x <= 11.0) leave = i;
    }
    area2 = truth[enter];
    const grid::InsertionOptions ins;
    grid::OccupancyGrid g1(0.05), g2(0.05);
    Random draws(11);
    auto visit = [&](AreaId area, const Pose2D& frame, size_t from, size_t to,
                     grid::OccupancyGrid* g, const Pose2D& error) {
      AreaVisit v{area, from, {}, {}};
      for (size_t i = from; i <= to; ++i) {
        const Pose2D draw(jitter_xy * draws.normal(), jitter_xy * draws.normal(),
                          jitter_theta * draws.normal());
        v.poses.push_back(error + (truth[i] - frame) + draw);
        if (g) grid::insert_scan(*g, v.poses.back(), log.steps[i].scan, ins);
      }
      visits.push_back(v);
    };
    const bool revisit_off = revisit_error.norm() > 0 || revisit_error.theta != 0;
    visit(1, Pose2D(), 0, enter, &g1, Pose2D());
    visit(2, area2, enter, leave, &g2, Pose2D());
    visit(1, Pose2D(), leave, truth.size() - 1, revisit_off ? nullptr : &g1, revisit_error);
    map.add_area(1);
    topology::ReferenceFrame f;
    f.parent = 1;
    f.origin_in_parent = area2;
    map.add_area(2, f);
    map.archive_map(1, g1);
    map.archive_map(2, g2);
    map.add_arc_measurement(1, 2, PoseGaussian(area2 + arc_error, arc_cov));
  }

  StepSource steps() const {
    return [this](uint64_t s) -> const LogStep* {
      return s < log.steps.size() ? &log.steps[static_cast<size_t>(s)] : nullptr;
    };
  }
};

double position_error(const Pose2D& a, const Pose2D& b) { return std::hypot(a.x - b.x, a.y - b.y); }
double angle_error(const Pose2D& a, const Pose2D& b) { return std::fabs(wrap_angle(a.theta - b.theta)); }

KeyframeGraph solve(const Scenario& s, const KeyframeGraphOptions& opt = {}, int threads = 1) {
  const GlobalPoses initial = optimize_poses(s.map, 1);
  return optimize_keyframe_graph(s.map, s.visits, s.steps(), initial, opt,
                                 metric_slam::MatcherOptions{}, threads);
}

TEST(KeyframeGraph, RecoversTheTruePosesWhereTheAreaEstimateIsOff) {
  const Scenario s(Pose2D(0.3, -0.2, 0.04), diag(0.1, 0.03));
  // The area-grain estimate carries the arc's error.
  const GlobalPoses areas = optimize_poses(s.map, 1);
  ASSERT_GT(position_error(areas.poses.at(2).mean, s.area2), 0.3);

  const KeyframeGraph g = solve(s);
  EXPECT_LT(position_error(g.areas.poses.at(2).mean, s.area2), 0.03);
  EXPECT_LT(angle_error(g.areas.poses.at(2).mean, s.area2), 0.005);
  EXPECT_EQ(g.areas.poses.at(1).mean.norm(), 0.0);  // the root stays put
  ASSERT_GT(g.nodes.size(), 50u);
  for (const KeyframeNode& n : g.nodes) {
    EXPECT_LT(position_error(n.global, s.truth[n.step]), 0.03) << "step " << n.step;
    EXPECT_LT(angle_error(n.global, s.truth[n.step]), 0.01) << "step " << n.step;
  }
  // Matches across the areas were found, and kept.
  EXPECT_GT(g.report.matches, 20u);
  EXPECT_EQ(g.report.arcs, 1u);
  EXPECT_EQ(g.report.in_area, g.nodes.size());
  EXPECT_EQ(g.report.consecutive, g.nodes.size() - 1);
  EXPECT_EQ(g.report.area_nodes, 2u);

  // Every step placed from its visit's keyframes: no jump where the areas
  // switch, every step within a few cm of the truth.
  const std::vector<Pose2D> traj = keyframe_trajectory(s.visits, g.nodes, 0, s.truth.size());
  for (size_t i = 0; i < traj.size(); ++i)
    EXPECT_LT(position_error(traj[i], s.truth[i]), 0.03) << "step " << i;
}

TEST(KeyframeGraph, ReportsWhetherTheRoundsSettled) {
  // The area estimate is 0.36 m off: the first round moves keyframes by
  // decimetres, the second by centimetres, and from the third on (each
  // keyframe matched afresh every round: match_reuse off) the matches' own
  // jitter (their optimum moves with the start by up to half a 5 cm cell)
  // moves some keyframe by 2-3 cm each round. With a tolerance of one cell
  // the rounds end early, and the report says so.
  const Scenario s(Pose2D(0.3, -0.2, 0.04), diag(0.1, 0.03));
  KeyframeGraphOptions opt;
  opt.match_reuse = false;
  opt.round_tolerance = 0.05;
  const KeyframeGraph settled = solve(s, opt);
  EXPECT_TRUE(settled.report.converged);
  EXPECT_LT(settled.report.rounds, opt.rounds);
  EXPECT_LE(settled.report.last_round_move_xy, opt.round_tolerance);
  EXPECT_LE(settled.report.last_round_move_theta, opt.round_tolerance);

  // Cut off after the first round, the report says that the estimate was
  // still moving, and by how much.
  KeyframeGraphOptions one = opt;
  one.rounds = 1;
  const KeyframeGraph cut = solve(s, one);
  EXPECT_EQ(cut.report.rounds, 1);
  EXPECT_FALSE(cut.report.converged);
  EXPECT_GT(cut.report.last_round_move_xy, 0.1);
}

TEST(KeyframeGraph, AStartThatBarelyMovedKeepsItsMatch) {
  // Re-matched every round, the matches' half-cell jitter moves some
  // keyframe by 2-3 cm a round and the rounds run out at a 1 cm tolerance.
  // Keeping the match of a start that moved less than the matcher's finest
  // step, the rounds reach a fixed point, and the poses are as good.
  // (Without the own areas' matches, whose extra round after the fixed
  // point moves the keyframes again.)
  const Scenario s(Pose2D(0.3, -0.2, 0.04), diag(0.1, 0.03));
  KeyframeGraphOptions opt;
  opt.match_own_area = false;
  opt.rounds = 10;
  opt.match_reuse = false;
  const KeyframeGraph fresh = solve(s, opt);
  opt.match_reuse = true;
  const KeyframeGraph kept = solve(s, opt);
  EXPECT_FALSE(fresh.report.converged);
  EXPECT_EQ(fresh.report.rounds, opt.rounds);
  EXPECT_GT(fresh.report.last_round_move_xy, opt.round_tolerance);
  EXPECT_TRUE(kept.report.converged);
  EXPECT_LT(kept.report.rounds, opt.rounds);
  // In the last round nearly every start had barely moved.
  EXPECT_GT(kept.report.matches_reused, kept.report.matches_tried * 9 / 10);
  EXPECT_EQ(fresh.report.matches_reused, 0u);
  for (const KeyframeNode& n : kept.nodes) {
    EXPECT_LT(position_error(n.global, s.truth[n.step]), 0.03) << "step " << n.step;
    EXPECT_LT(angle_error(n.global, s.truth[n.step]), 0.01) << "step " << n.step;
  }
}

TEST(KeyframeGraph, RecoversAMisplacedRevisitInsideAnArea) {
  // The arc is right; the error is inside area 1: its second visit's poses
  // are 0.15 m and 0.02 rad off, so placing whole areas puts that stretch
  // of the trajectory off by up to as much and more.
  const Scenario s(Pose2D(), diag(0.1, 0.03), Pose2D(0.12, -0.09, 0.02));
  const AreaVisit& revisit = s.visits.back();
  const GlobalPoses areas = optimize_poses(s.map, 1);
  double worst = 0.0;
  for (size_t k = 0; k < revisit.poses.size(); ++k)
    worst = std::max(worst, position_error(areas.poses.at(1).mean + revisit.poses[k],
                                           s.truth[revisit.first_step + k]));
  ASSERT_GT(worst, 0.1);

  const KeyframeGraph g = solve(s);
  const std::vector<Pose2D> traj = keyframe_trajectory(s.visits, g.nodes, 0, s.truth.size());
  for (size_t i = revisit.first_step; i < s.truth.size(); ++i)
    EXPECT_LT(position_error(traj[i], s.truth[i]), 0.04) << "step " << i;
}

// The RMS position error of the keyframes against the truth.
double keyframes_rms(const KeyframeGraph& g, const Scenario& s) {
  double sum = 0.0;
  for (const KeyframeNode& n : g.nodes) sum += std::pow(position_error(n.global, s.truth[n.step]), 2);
  return std::sqrt(sum / static_cast<double>(g.nodes.size()));
}

TEST(KeyframeGraph, MatchesInTheKeyframesOwnAreaSmoothTheFiltersDraws) {
  // The arc is right, but every pose of the filter's path carries its own
  // draw (3 cm, 0.01 rad), and the grids were built at those poses. Tied by
  // its in-area pose, its motion and its matches in the other area, a
  // keyframe keeps much of its draw; matched in its own area's grid as well
  // (the default), it is placed against walls that all the area's scans
  // drew, and ends a third nearer the truth.
  const Scenario s(Pose2D(), diag(0.1, 0.03), Pose2D(), 0.03, 0.01);
  KeyframeGraphOptions others_only;
  others_only.match_own_area = false;
  const KeyframeGraph own = solve(s), others = solve(s, others_only);
  ASSERT_EQ(own.nodes.size(), others.nodes.size());
  EXPECT_GT(own.report.matches, others.report.matches + own.nodes.size() / 2);
  const double own_rms = keyframes_rms(own, s), others_rms = keyframes_rms(others, s);
  EXPECT_GT(others_rms, 0.05);  // 6.8 cm
  EXPECT_LT(own_rms, 0.75 * others_rms);  // 4.5 cm
}

TEST(KeyframeGraph, TheOwnAreasJoinOnceTheEstimateSettled) {
  // Without the own areas' matches the rounds settle and stop; with them,
  // one more round adds them at the settled estimate, and then the rounds
  // stop whatever it moved.
  const Scenario s(Pose2D(0.3, -0.2, 0.04), diag(0.1, 0.03));
  KeyframeGraphOptions opt;
  opt.rounds = 20;
  opt.match_own_area = false;
  const KeyframeGraph others = solve(s, opt);
  opt.match_own_area = true;
  const KeyframeGraph own = solve(s, opt);
  ASSERT_TRUE(others.report.converged);
  ASSERT_LT(others.report.rounds + 1, opt.rounds);
  EXPECT_EQ(own.report.rounds, others.report.rounds + 1);
  EXPECT_GT(own.report.matches, others.report.matches + own.nodes.size() / 2);
  // With a single round, that round is the last one: the own areas join.
  opt.rounds = 1;
  const size_t with = solve(s, opt).report.matches;
  opt.match_own_area = false;
  EXPECT_GT(with, solve(s, opt).report.matches + own.nodes.size() / 2);
}

// A blind stretch in area 2 (steps b0..b1: the laser returns nothing), as
// the filter leaves it: its poses from b0 on turned about the pose at b0 by
// 0.005 rad a blind step (the odometry's drift, which no scan corrected),
// and the rest of the visit carrying that turn, area 2's grid drawn at
// those poses. `with_error`: the visit also holds the blind error (as
// GridRbpf::blind_trace() gives it): 0.05 m and 0.02 rad a blind step.
void blind_stretch(Scenario* s, size_t b0, size_t b1, bool with_error) {
  AreaVisit& v = s->visits[1];
  const size_t first = v.first_step, n = v.poses.size();
  const Pose2D pivot = v.poses[b0 - first];
  for (size_t k = b0; k < first + n; ++k) {
    const double turn = 0.005 * static_cast<double>(std::min(k, b1) - b0);
    v.poses[k - first] = pivot + Pose2D(0.0, 0.0, turn) + (v.poses[k - first] - pivot);
  }
  for (size_t k = b0; k <= b1; ++k)
    std::fill(s->log.steps[k].scan.ranges.begin(), s->log.steps[k].scan.ranges.end(), 0.0f);
  grid::OccupancyGrid g2(0.05);
  for (size_t k = first; k < first + n; ++k)
    grid::insert_scan(g2, v.poses[k - first], s->log.steps[k].scan, grid::InsertionOptions());
  s->map.archive_map(2, g2);
  if (!with_error) return;
  for (size_t k = first; k < first + n; ++k) {
    const double steps = k < b0 ? 0.0 : static_cast<double>(std::min(k, b1) - b0 + 1);
    v.blind.push_back(steps * diag(0.05, 0.02));
  }
}

// The keyframes of area 2 from step `from` on: RMS position error.
double area2_rms_from(const KeyframeGraph& g, const Scenario& s, size_t from) {
  double sum = 0.0;
  size_t count = 0;
  for (const KeyframeNode& n : g.nodes)
    if (n.area == 2 && n.step >= from) {
      sum += std::pow(position_error(n.global, s.truth[n.step]), 2);
      ++count;
    }
  EXPECT_GT(count, 5u);
  return count ? std::sqrt(sum / static_cast<double>(count)) : 0.0;
}

TEST(KeyframeGraph, AStretchWithoutReturnsBendsWhereItsErrorIsKnown) {
  // Area 2's visit ends with 50 steps of a blind laser, the path there
  // turning away by 0.005 rad a step; then the robot is back in area 1,
  // whose poses are right. With the blind error, the stretch's ties to
  // area 2 give way, and the odometry's motion from its start and to area
  // 1's first keyframe bend it towards the truth; without it, area 2 holds
  // the stretch as the filter left it, decimetres off towards its end.
  Scenario blind(Pose2D(), diag(0.05, 0.02)), rigid(Pose2D(), diag(0.05, 0.02));
  const AreaVisit& v = blind.visits[1];
  const size_t b1 = v.first_step + v.poses.size() - 1, b0 = b1 - 50;
  blind_stretch(&blind, b0, b1, true);
  blind_stretch(&rigid, b0, b1, false);
  const KeyframeGraph bent = solve(blind), held = solve(rigid);
  const double bent_rms = area2_rms_from(bent, blind, b0);
  const double held_rms = area2_rms_from(held, rigid, b0);
  EXPECT_GT(held_rms, 0.25) << "bent " << bent_rms;
  EXPECT_LT(bent_rms, 0.5 * held_rms) << "held " << held_rms;
  // Before the stretch, area 2 is placed as well either way.
  EXPECT_LT(position_error(bent.areas.poses.at(2).mean, blind.area2), 0.05);
  EXPECT_LT(area2_rms_from(bent, blind, 0), area2_rms_from(held, rigid, 0));
}

TEST(KeyframeGraph, AConfidentWrongArcIsDownWeighted) {
  // The arc is off by 0.4 m but claims 3 cm: without the robust kernel it
  // would drag area 2 most of the way; with it the matches win. Undoing
  // 0.4 m takes more rounds than the default five (the fifth still moves
  // keyframes by 0.2 m), so the test looks at where the rounds settle.
  const Scenario s(Pose2D(0.4, 0.0, 0.0), diag(0.03, 0.01));
  KeyframeGraphOptions opt;
  opt.rounds = 20;
  const KeyframeGraph g = solve(s, opt);
  EXPECT_LT(position_error(g.areas.poses.at(2).mean, s.area2), 0.03);
  EXPECT_GE(g.report.down_weighted, 1u);
}

TEST(KeyframeGraph, AnArcTheAreaFitSwitchedOffIsLeftOut) {
  // The same wrong arc, named as an outlier (as optimize_poses reports
  // one): it is no constraint at all, and the path and matches place area 2
  // (from 0.4 m off, as above: where the rounds settle).
  const Scenario s(Pose2D(0.4, 0.0, 0.0), diag(0.03, 0.01));
  const GlobalPoses initial = optimize_poses(s.map, 1);
  KeyframeGraphOptions opt;
  opt.rounds = 20;
  const KeyframeGraph with = solve(s, opt);
  const KeyframeGraph without = optimize_keyframe_graph(
      s.map, s.visits, s.steps(), initial, opt, metric_slam::MatcherOptions{}, 1,
      {OutlierArc{2, 1, 100.0}});  // either direction names the arc
  EXPECT_EQ(without.report.arcs + 1, with.report.arcs);
  EXPECT_LT(position_error(without.areas.poses.at(2).mean, s.area2), 0.03);
}

TEST(KeyframeGraph, WithoutMatchesThePathStillJoinsTheAreas) {
  // The switching steps are known in both areas' frames, so even with no
  // scan matching the consecutive constraints outweigh a loose wrong arc.
  const Scenario s(Pose2D(0.3, -0.2, 0.04), diag(0.3, 0.1));
  KeyframeGraphOptions opt;
  opt.match = false;
  const KeyframeGraph g = solve(s, opt);
  EXPECT_EQ(g.report.matches, 0u);
  EXPECT_LT(position_error(g.areas.poses.at(2).mean, s.area2), 0.1);
}

TEST(KeyframeTrajectory, StepsBetweenTwoNodesPassSmoothlyFromOneCorrectionToTheNext) {
  // One visit of 11 steps 0.1 m apart along x in its area's frame; nodes at
  // steps 0 and 10. The graph moved the second node 0.1 m further in y and
  // turned it 0.02 rad more than the first: seen from the second node, the
  // steps lie about 0.09 m from where the first puts them, so placing each
  // from the nearer node alone would jump 0.09 m half way. Blended, the
  // steps go from the one correction to the other a little at a time.
  AreaVisit v;
  v.area = 1;
  v.first_step = 0;
  for (int k = 0; k <= 10; ++k) v.poses.emplace_back(0.1 * k, 0.0, 0.0);
  std::vector<KeyframeNode> nodes(2);
  nodes[0] = {1, 0, 0, v.poses[0], Pose2D(5.0, 2.0, 0.0)};
  nodes[1] = {1, 0, 10, v.poses[10], Pose2D(6.0, 2.1, 0.02)};
  const std::vector<Pose2D> t = keyframe_trajectory({v}, nodes, 0, 11);
  ASSERT_EQ(t.size(), 11u);
  EXPECT_NEAR(t[0].x, 5.0, 1e-12);
  EXPECT_NEAR(t[0].y, 2.0, 1e-12);
  EXPECT_NEAR(t[10].y, 2.1, 1e-12);
  EXPECT_NEAR(t[10].theta, 0.02, 1e-12);
  for (int k = 1; k <= 10; ++k) {
    EXPECT_NEAR(t[k].theta - t[k - 1].theta, 0.002, 1e-12) << "step " << k;
    EXPECT_NEAR(t[k].x - t[k - 1].x, 0.1, 1e-3) << "step " << k;
    EXPECT_GT(t[k].y - t[k - 1].y, 0.005) << "step " << k;
    EXPECT_LT(t[k].y - t[k - 1].y, 0.012) << "step " << k;
  }
  // Beyond the last node, the steps follow it alone.
  AreaVisit longer = v;
  longer.poses.emplace_back(1.1, 0.0, 0.0);
  const std::vector<Pose2D> u = keyframe_trajectory({longer}, nodes, 0, 12);
  EXPECT_NEAR(u[11].x, 6.0 + 0.1 * std::cos(0.02), 1e-9);
  EXPECT_NEAR(u[11].y, 2.1 + 0.1 * std::sin(0.02), 1e-9);
}

TEST(KeyframeTrajectory, NodesAtOnePlaceBlendByStep) {
  // The robot turns on the spot between the two nodes: no path length, so
  // the blend goes by steps.
  AreaVisit v;
  v.area = 1;
  for (int k = 0; k <= 4; ++k) v.poses.emplace_back(0.0, 0.0, 0.1 * k);
  std::vector<KeyframeNode> nodes(2);
  nodes[0] = {1, 0, 0, v.poses[0], Pose2D(1.0, 0.0, 0.0)};
  nodes[1] = {1, 0, 4, v.poses[4], Pose2D(1.2, 0.0, 0.4)};
  const std::vector<Pose2D> t = keyframe_trajectory({v}, nodes, 0, 5);
  for (int k = 0; k <= 4; ++k) {
    EXPECT_NEAR(t[k].x, 1.0 + 0.05 * k, 1e-12) << "step " << k;
    EXPECT_NEAR(t[k].theta, 0.1 * k, 1e-12) << "step " << k;
  }
}

TEST(KeyframeGraph, SameInputSameOutputWhateverTheThreads) {
  const Scenario s(Pose2D(0.3, -0.2, 0.04), diag(0.1, 0.03));
  // Twice on one thread, and on three.
  const KeyframeGraph a = solve(s), b = solve(s), c = solve(s, {}, 3);
  for (const KeyframeGraph* other : {&b, &c}) {
    ASSERT_EQ(a.nodes.size(), other->nodes.size());
    for (size_t i = 0; i < a.nodes.size(); ++i) {
      EXPECT_EQ(a.nodes[i].global.x, other->nodes[i].global.x);
      EXPECT_EQ(a.nodes[i].global.y, other->nodes[i].global.y);
      EXPECT_EQ(a.nodes[i].global.theta, other->nodes[i].global.theta);
    }
    EXPECT_EQ(a.report.matches, other->report.matches);
    EXPECT_EQ(a.report.iterations, other->report.iterations);
  }
  ASSERT_EQ(a.nodes.size(), b.nodes.size());
  for (size_t i = 0; i < a.nodes.size(); ++i) {
    EXPECT_EQ(a.nodes[i].step, b.nodes[i].step);
    EXPECT_EQ(a.nodes[i].global.x, b.nodes[i].global.x);
    EXPECT_EQ(a.nodes[i].global.y, b.nodes[i].global.y);
    EXPECT_EQ(a.nodes[i].global.theta, b.nodes[i].global.theta);
  }
  for (const AreaId id : {1u, 2u}) {
    EXPECT_EQ(a.areas.poses.at(id).mean.x, b.areas.poses.at(id).mean.x);
    EXPECT_EQ(a.areas.poses.at(id).mean.y, b.areas.poses.at(id).mean.y);
    EXPECT_EQ(a.areas.poses.at(id).mean.theta, b.areas.poses.at(id).mean.theta);
    EXPECT_TRUE(a.areas.poses.at(id).cov == b.areas.poses.at(id).cov);
  }
  EXPECT_EQ(a.report.matches, b.report.matches);
  EXPECT_EQ(a.report.iterations, b.report.iterations);
}

TEST(KeyframeGraph, GridDrawnFromTheKeyframeScans) {
  const Scenario s(Pose2D(0.3, -0.2, 0.04), diag(0.1, 0.03));
  const KeyframeGraph g = solve(s);
  const grid::OccupancyGrid m =
      render_keyframe_grid(g.nodes, s.steps(), 0.05, grid::InsertionOptions{});
  // The inner wall's face (x = 8, where a cell begins: its returns fall in
  // the cell [8, 8.05)) is an obstacle, the room beside it free.
  EXPECT_GT(m.probability(m.cell_of(8.01, 3.0)), 0.6);
  EXPECT_LT(m.probability(m.cell_of(7.0, 3.0)), 0.4);
  EXPECT_THROW(render_keyframe_grid(g.nodes, s.steps(), 0.0, grid::InsertionOptions{}),
               std::invalid_argument);
}

TEST(KeyframeGraph, RejectsAnUnknownRootAndAnEmptyPath) {
  const Scenario s(Pose2D(), diag(0.1, 0.03));
  GlobalPoses initial = optimize_poses(s.map, 1);
  initial.root = 9;
  EXPECT_THROW(optimize_keyframe_graph(s.map, s.visits, s.steps(), initial, {}, {}),
               std::invalid_argument);
  const StepSource none = [](uint64_t) -> const LogStep* { return nullptr; };
  EXPECT_THROW(optimize_keyframe_graph(s.map, s.visits, none, optimize_poses(s.map, 1), {}, {}),
               std::invalid_argument);
}

}  // namespace
}  // namespace hmt::global_map
