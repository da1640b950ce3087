#include "hmt/metric_slam/grid_rbpf.h"

#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>

#include "hmt/common/config.h"
#include "hmt/common/error.h"
#include "sim_world.h"

namespace hmt::metric_slam {
namespace {

// A loop around the inner wall of the simulated office.
testing_sim::SimRun loop_run(uint64_t seed) {
  return testing_sim::simulate({{2, 2, 0}, {6, 2, 0}, {6, 8, 0}, {12, 8, 0},
                                {12, 3, 0}, {18, 3, 0}, {18, 8, 0}, {10, 8.5, 0},
                                {2, 8, 0}, {2, 2, 0}},
                               0.3, seed, 0.08);
}

// The simulated logs step 0.3 m: these tests are of what the filter does
// at a step, so it filters every one (the default spacing, 0.5 m, would skip
// every other; ScansCloserThanTheSpacingAreNotWeighedAgain tests it).
RbpfOptions small_filter(int threads) {
  RbpfOptions o;
  o.particles = 10;
  o.threads = threads;
  o.seed = 5;
  o.update_distance = 0.05;
  return o;
}

TEST(GridRbpf, TracksBetterThanOdometry) {
  const auto run = loop_run(11);
  GridRbpf f(small_filter(2));
  for (const auto& st : run.log.steps) f.process(st);
  EXPECT_EQ(f.stats().steps, run.log.steps.size());
  // Estimates are relative to the first pose.
  const Pose2D est = run.truth.front() + f.best().pose;
  const Pose2D truth = run.truth.back();
  const Pose2D odo = testing_sim::dead_reckoning(run);
  const double err = std::hypot(est.x - truth.x, est.y - truth.y);
  const double odo_err = std::hypot(odo.x - truth.x, odo.y - truth.y);
  EXPECT_LT(err, 0.15) << "odometry error was " << odo_err;
  EXPECT_LT(err, odo_err);
  EXPECT_EQ(f.best().path.size(), run.log.steps.size());
  // Every particle moved at every filtered step (the first scan only
  // starts the map), and in this world the scans match: no particle-step
  // fell back to the odometry.
  const RbpfStats& s = f.stats();
  EXPECT_GT(s.steps - s.skipped_steps, run.log.steps.size() / 2);
  EXPECT_EQ(s.particle_moves, (s.steps - 1 - s.skipped_steps) * f.particles().size());
  EXPECT_EQ(s.odometry_fallbacks, 0u);
}

// A scan nearer the last filtered one than update_distance (within half its
// own step of it: the scan nearest the spacing is the one filtered) and
// turned less than update_angle is not weighed: the paths go on by the
// odometry, and the next filtered step moves the particles by all of the
// motion since. On the 0.3 m loop the default spacing filters about every
// other scan on the straights and every scan through the turns.
TEST(GridRbpf, ScansCloserThanTheSpacingAreNotWeighedAgain) {
  const auto run = loop_run(11);
  RbpfOptions o = small_filter(2);
  const RbpfOptions defaults;
  o.update_distance = defaults.update_distance;
  o.update_angle = defaults.update_angle;
  ASSERT_EQ(o.update_distance, 0.5);
  ASSERT_EQ(o.update_angle, 0.05);
  GridRbpf f(o);
  f.process(run.log.steps[0]);
  Pose2D pending;
  size_t filtered = 0;
  for (size_t i = 1; i < run.log.steps.size(); ++i) {
    const LogStep& st = run.log.steps[i];
    const size_t skipped = f.stats().skipped_steps;
    std::vector<Pose2D> poses;
    for (const Particle& p : f.particles()) poses.push_back(p.pose);
    f.process(st);
    pending = pending + st.odometry_increment;
    const bool due = pending.norm() >= 0.5 - 0.5 * st.odometry_increment.norm() ||
                     std::fabs(pending.theta) >= 0.05;
    ASSERT_EQ(f.stats().skipped_steps == skipped, due) << "step " << i;
    if (due) {
      pending = Pose2D();
      ++filtered;
      continue;
    }
    // Skipped: the particles stay where the last filtered step put them,
    // their paths extended by the odometry since.
    for (size_t k = 0; k < poses.size(); ++k) {
      const Particle& p = f.particles()[k];
      EXPECT_EQ(p.pose.x, poses[k].x);
      const Pose2D want = poses[k] + pending;
      EXPECT_NEAR(p.path.back().x, want.x, 1e-12);
      EXPECT_NEAR(p.path.back().y, want.y, 1e-12);
      EXPECT_NEAR(wrap_angle(p.path.back().theta - want.theta), 0.0, 1e-12);
    }
  }
  const size_t n = run.log.steps.size() - 1;
  EXPECT_GT(filtered, n / 3);
  EXPECT_LT(filtered, 3 * n / 4);
  EXPECT_EQ(f.stats().particle_moves, filtered * f.particles().size());
  EXPECT_EQ(f.best().path.size(), run.log.steps.size());
  // And it still tracks: the loop ends nearer the truth than the odometry.
  const Pose2D est = run.truth.front() + f.best().pose;
  const Pose2D odo = testing_sim::dead_reckoning(run);
  const Pose2D& truth = run.truth.back();
  EXPECT_LT(std::hypot(est.x - truth.x, est.y - truth.y),
            0.5 * std::hypot(odo.x - truth.x, odo.y - truth.y));
}

// A log thinned to steps a little short of the spacing (0.48 m) is filtered
// whole: the scan nearest each half metre is filtered, not the first past it
// (which would take every other scan, a metre apart).
TEST(GridRbpf, ALogThinnedToAboutTheSpacingIsFilteredWhole) {
  const auto run = testing_sim::simulate({{2, 2, 0}, {2 + 30 * 0.48, 2, 0}}, 0.48, 3, 0.01);
  RbpfOptions o = small_filter(1);
  o.update_distance = RbpfOptions().update_distance;
  ASSERT_EQ(o.update_distance, 0.5);
  GridRbpf f(o);
  for (const auto& st : run.log.steps) {
    ASSERT_LT(st.odometry_increment.norm(), 0.5);
    f.process(st);
  }
  EXPECT_EQ(run.log.steps.size(), 31u);
  EXPECT_EQ(f.stats().skipped_steps, 0u);
}

// A particle moves to a pose drawn from its proposal; its estimates record
// the proposal's mean. At the first filtered step every particle starts from
// one pose in one map, so they share one proposal: the draws differ, the
// estimates do not, and they lie where the robot went.
TEST(GridRbpf, TheEstimatesAreTheProposalsMeanNotTheDraw) {
  const auto run = loop_run(11);
  GridRbpf f(small_filter(2));
  f.process(run.log.steps[0]);
  f.process(run.log.steps[1]);
  ASSERT_EQ(f.stats().skipped_steps, 0u);
  ASSERT_EQ(f.stats().odometry_fallbacks, 0u);
  const Pose2D truth = run.truth[1] - run.truth[0];
  const Pose2D mean = f.particles()[0].estimates.back();
  bool draws_differ = false;
  for (const Particle& p : f.particles()) {
    ASSERT_EQ(p.estimates.size(), 2u);
    ASSERT_EQ(p.path.size(), 2u);
    EXPECT_EQ(p.estimates.back().x, mean.x);
    EXPECT_EQ(p.estimates.back().y, mean.y);
    EXPECT_EQ(p.estimates.back().theta, mean.theta);
    // The path holds the draw, which the filter goes on from.
    EXPECT_EQ(p.path.back().x, p.pose.x);
    EXPECT_EQ(p.path.back().theta, p.pose.theta);
    draws_differ |= p.pose.x != mean.x || p.pose.y != mean.y || p.pose.theta != mean.theta;
  }
  EXPECT_TRUE(draws_differ);
  EXPECT_LT(std::hypot(mean.x - truth.x, mean.y - truth.y), 0.05);
  EXPECT_LT(std::fabs(wrap_angle(mean.theta - truth.theta)), 0.02);
}

// Over a whole loop the estimates follow the true motion from step to step
// more closely than the draws do: the draws add the proposal's spread to
// every step, the estimates only what the match leaves.
TEST(GridRbpf, TheEstimatesMoveStepToStepAsTheRobotDidBetterThanTheDraws) {
  const auto run = loop_run(12);
  RbpfOptions o = small_filter(2);
  o.proposal_gain = 10;  // a proposal wide enough that its spread shows
  GridRbpf f(o);
  for (const auto& st : run.log.steps) f.process(st);
  const Particle& b = f.best();
  ASSERT_EQ(b.path.size(), run.log.steps.size());
  ASSERT_EQ(b.estimates.size(), run.log.steps.size());
  auto step_error = [&](const std::vector<Pose2D>& poses) {
    double sum = 0.0;
    for (size_t k = 1; k < poses.size(); ++k) {
      const Pose2D e = (poses[k] - poses[k - 1]) - (run.truth[k] - run.truth[k - 1]);
      sum += e.norm();
    }
    return sum / static_cast<double>(poses.size() - 1);
  };
  const double drawn = step_error(b.path), estimated = step_error(b.estimates);
  EXPECT_LT(estimated, 0.8 * drawn) << "estimates " << estimated << " m, draws " << drawn << " m";
}

// The odometry of a few steps reports a turn the robot did not make (a
// slipping wheel): 0.7 rad each, more than the hill climbing alone recovers
// from in this world (it does from 0.5).
testing_sim::SimRun with_false_turns(testing_sim::SimRun run) {
  for (size_t i : {20u, 45u, 70u}) run.log.steps.at(i).odometry_increment.theta += 0.7;
  return run;
}

double final_heading_error(const testing_sim::SimRun& run, const RbpfOptions& o) {
  GridRbpf f(o);
  for (const auto& st : run.log.steps) f.process(st);
  const Pose2D est = run.truth.front() + f.best().pose;
  return std::fabs(wrap_angle(est.theta - run.truth.back().theta));
}

TEST(GridRbpf, HeadingSearchRecoversFromAFalseTurnInTheOdometry) {
  const auto run = with_false_turns(loop_run(11));
  RbpfOptions on = small_filter(2), off = small_filter(2);
  ASSERT_GT(on.heading_search_ratio, 0.0);  // the default searches
  off.heading_search_ratio = 0.0;
  // Without the search the filter keeps (some of) the false turns.
  EXPECT_GT(final_heading_error(run, off), 0.2);
  EXPECT_LT(final_heading_error(run, on), 0.05);
}

TEST(GridRbpf, AScanWithNothingInRangeMovesEveryParticleByTheOdometry) {
  const auto run = testing_sim::with_sparse_scans(loop_run(11), 30, 39, 0);
  GridRbpf f(small_filter(2));
  for (size_t i = 0; i < 30; ++i) f.process(run.log.steps[i]);
  for (size_t i = 30; i <= 39; ++i) {
    std::vector<Pose2D> before;
    for (const auto& p : f.particles()) before.push_back(p.pose);
    f.process(run.log.steps[i]);
    // Nothing to match: no weight changes, so no resampling reorders them.
    ASSERT_EQ(f.particles().size(), before.size());
    for (size_t k = 0; k < before.size(); ++k) {
      const Pose2D want = before[k] + run.log.steps[i].odometry_increment;
      const Pose2D& got = f.particles()[k].pose;
      EXPECT_NEAR(got.x, want.x, 1e-12) << "step " << i << " particle " << k;
      EXPECT_NEAR(got.y, want.y, 1e-12) << "step " << i << " particle " << k;
      EXPECT_NEAR(wrap_angle(got.theta - want.theta), 0.0, 1e-12)
          << "step " << i << " particle " << k;
    }
  }
}

// Five metres of open ground in the office (steps kBlindFirst-kBlindLast,
// no returns at all), with odometry as good as a robot's on pavement.
constexpr size_t kBlindFirst = 40, kBlindLast = 56;
testing_sim::SimRun open_ground_run() {
  return testing_sim::with_sparse_scans(
      testing_sim::simulate({{2, 2, 0}, {6, 2, 0}, {6, 8, 0}, {12, 8, 0}, {12, 3, 0},
                             {18, 3, 0}, {18, 8, 0}},
                            0.3, 21, 0.01),
      kBlindFirst, kBlindLast, 0);
}

// Over four seeds the filter leaves the open ground with the odometry's
// heading error, not with the motion model's spread (0.1 rad per metre by
// default, drawn at every step while no scan could pick among the
// particles: 0.5 rad off at worst).
TEST(GridRbpf, AStretchWithoutReturnsCostsNoMoreHeadingThanTheOdometry) {
  const size_t first = kBlindFirst, last = kBlindLast;
  const auto run = open_ground_run();
  double worst = 0.0;
  for (uint64_t seed = 1; seed <= 4; ++seed) {
    RbpfOptions o = small_filter(2);
    o.seed = seed;
    GridRbpf f(o);
    for (size_t i = 0; i <= last; ++i) f.process(run.log.steps[i]);
    const Pose2D est = run.truth.front() + f.best().pose;
    worst = std::max(worst, std::fabs(wrap_angle(est.theta - run.truth[last].theta)));
  }
  const Pose2D dr = testing_sim::dead_reckoning(run, first, last);
  const double odo = std::fabs(wrap_angle(dr.theta - run.truth[last].theta));
  // What the filter had before the stretch (a few mrad) plus the odometry's.
  EXPECT_LT(worst, odo + 0.02) << "odometry's own error " << odo;
}

TEST(GridRbpf, AStretchWithoutReturnsKeepsTheErrorTheParticlesDoNotSpread) {
  // The same stretch: the particles follow the odometry alone there, so
  // their spread stays as it was; blind_cov() holds the motion model's error
  // those steps add, growing step by step, and is zero where scans weigh.
  const size_t first = kBlindFirst, last = kBlindLast;
  const auto run = open_ground_run();
  GridRbpf f(small_filter(2));
  for (size_t i = 0; i < first; ++i) f.process(run.log.steps[i]);
  EXPECT_TRUE(f.blind_cov().isZero());
  EXPECT_TRUE(f.blind_trace().empty());  // no step blind yet: nothing held
  // The heading's variance grows by the model's at every processed step.
  double heading = 0.0;
  size_t grew = 0;
  for (size_t i = first; i <= last; ++i) {
    f.process(run.log.steps[i]);
    const double h = f.blind_cov()(2, 2);
    EXPECT_GE(h, heading) << "step " << i;
    grew += h > heading;
    heading = h;
  }
  const double trace = f.blind_cov().trace();
  // The steps the filter processed (it skips those that barely moved).
  EXPECT_GE(grew, (last - first) / 2);
  const Eigen::Matrix3d c = f.blind_cov();
  EXPECT_TRUE(c.isApprox(c.transpose()));
  EXPECT_GT(c.ldlt().vectorD().minCoeff(), 0.0);
  // Each step adds at least the motion model's floors: 16 steps of 0.3 m.
  EXPECT_GT(std::sqrt(c(0, 0) + c(1, 1)), 0.05);
  // Scans again: the error stays until an area begins, which takes it.
  f.process(run.log.steps[last + 1]);
  EXPECT_EQ(f.blind_cov().trace(), trace);
  // The trace: blind_cov() at every step of the paths, zero before the
  // stretch (skipped steps too), as it stood after each step in it.
  const std::vector<Eigen::Matrix3d>& t = f.blind_trace();
  ASSERT_EQ(t.size(), f.best().path.size());
  ASSERT_EQ(t.size(), f.best().estimates.size());
  EXPECT_TRUE(t[first - 1].isZero());
  EXPECT_EQ(t.back(), f.blind_cov());
  EXPECT_EQ(t[last](2, 2), heading);
  for (size_t i = first; i <= last; ++i) EXPECT_GE(t[i](2, 2), t[i - 1](2, 2)) << "step " << i;
  f.start_new_area();
  EXPECT_TRUE(f.blind_cov().isZero());
  EXPECT_TRUE(f.blind_trace().empty());
  // Blind steps in the new area: the trace holds every step of it.
  for (size_t i = first; i < first + 4; ++i) f.process(run.log.steps[i]);
  ASSERT_FALSE(f.blind_trace().empty());
  EXPECT_EQ(f.blind_trace().size(), f.best().path.size());
  EXPECT_TRUE(f.blind_trace().front().isZero());
}

TEST(RbpfOptions, BadHeadingSearchValuesAreConfigErrorsNamingTheKey) {
  for (const char* bad : {"heading_search_ratio = 1.5", "heading_search_ratio = -0.1",
                          "heading_search_range = 4", "heading_search_range = -1",
                          "heading_search_ratio = half"}) {
    Config cfg = Config::from_string(std::string("[metric_slam]\n") + bad + "\n", "test");
    RbpfOptions o;
    try {
      o.load(cfg);
      ADD_FAILURE() << "accepted: " << bad;
    } catch (const ConfigError& e) {
      const std::string key = std::string(bad).substr(0, std::string(bad).find(' '));
      EXPECT_NE(std::string(e.what()).find(key), std::string::npos) << e.what();
    }
  }
}

TEST(GridRbpf, DeterministicWhateverTheThreadCount) {
  const auto run = loop_run(12);
  GridRbpf a(small_filter(1)), b(small_filter(3));
  for (const auto& st : run.log.steps) {
    a.process(st);
    b.process(st);
  }
  ASSERT_EQ(a.best_index(), b.best_index());
  const auto& pa = a.best().path;
  const auto& pb = b.best().path;
  ASSERT_EQ(pa.size(), pb.size());
  for (size_t i = 0; i < pa.size(); ++i) {
    EXPECT_EQ(pa[i].x, pb[i].x);
    EXPECT_EQ(pa[i].theta, pb[i].theta);
  }
}

// The split step (what the hybrid filter runs for all its hypotheses in one
// loop) is process() exactly, whatever order the particles move in.
TEST(GridRbpf, SplitStepInAnyOrderIsProcess) {
  const auto run = loop_run(13);
  GridRbpf a(small_filter(1)), b(small_filter(1));
  size_t moved_steps = 0;
  for (const auto& st : run.log.steps) {
    a.process(st);
    if (b.begin_step(st)) {
      ++moved_steps;
      ASSERT_GT(b.pending_moves(), 0u);
      ASSERT_LE(b.pending_moves(), b.particles().size());
      for (size_t i = b.pending_moves(); i-- > 0;) b.move(i);
      b.end_step();
    } else {
      EXPECT_EQ(b.pending_moves(), 0u);
    }
    ASSERT_EQ(a.last_log_evidence(), b.last_log_evidence());
  }
  EXPECT_GT(moved_steps, run.log.steps.size() / 2);
  EXPECT_EQ(a.stats().resamplings, b.stats().resamplings);
  ASSERT_EQ(a.particles().size(), b.particles().size());
  for (size_t i = 0; i < a.particles().size(); ++i) {
    const Particle& pa = a.particles()[i];
    const Particle& pb = b.particles()[i];
    EXPECT_EQ(pa.pose.x, pb.pose.x);
    EXPECT_EQ(pa.pose.y, pb.pose.y);
    EXPECT_EQ(pa.pose.theta, pb.pose.theta);
    EXPECT_EQ(pa.log_weight, pb.log_weight);
  }
}

// Particles that start a step from one pose on one map (every particle at
// the first step, and after a new area; the copies a resampling makes) move
// as one group: one match and one lattice, yet each its own draw. Particles
// whose poses or maps differ are never grouped.
TEST(GridRbpf, ParticlesStartingAlikeMoveAsOneGroup) {
  const auto run = loop_run(16);
  GridRbpf f(small_filter(2));
  const size_t n = f.options().particles;
  f.process(run.log.steps[0]);  // the first scan starts the map
  size_t k = 1;
  while (!f.begin_step(run.log.steps[k])) ++k;
  ++k;
  ASSERT_EQ(f.pending_moves(), 1u);  // all alike
  f.move(0);
  f.end_step();
  EXPECT_EQ(f.stats().shared_starts, n - 1);
  EXPECT_EQ(f.stats().odometry_fallbacks, 0u);
  for (const Particle& p : f.particles()) {
    // One proposal: the same mean and weight; draws of their own.
    EXPECT_EQ(p.estimates.back().x, f.particles()[0].estimates.back().x);
    EXPECT_EQ(p.estimates.back().theta, f.particles()[0].estimates.back().theta);
    EXPECT_EQ(p.log_weight, f.particles()[0].log_weight);
  }
  for (size_t i = 1; i < n; ++i)
    EXPECT_NE(f.particles()[i].pose.x, f.particles()[0].pose.x) << "particle " << i;
  // Equal weights: no resampling, so each particle now has its own pose and
  // its own map.
  ASSERT_EQ(f.stats().resamplings, 0u);
  while (!f.begin_step(run.log.steps[k])) ++k;
  ++k;
  EXPECT_EQ(f.pending_moves(), n);
  for (size_t g = 0; g < f.pending_moves(); ++g) f.move(g);
  f.end_step();
  EXPECT_EQ(f.stats().shared_starts, n - 1);
  // Twice as many particles drawn from these: the copies of one particle
  // share its pose and map, and move together.
  f.resize(2 * n);
  const std::vector<Particle> drawn = f.particles();
  size_t distinct = 0;
  for (size_t i = 0; i < drawn.size(); ++i) {
    bool copy = false;
    for (size_t j = 0; j < i && !copy; ++j)
      copy = drawn[j].pose.x == drawn[i].pose.x && drawn[j].pose.y == drawn[i].pose.y &&
             drawn[j].pose.theta == drawn[i].pose.theta &&
             drawn[j].map.shares_every_tile_with(drawn[i].map);
    distinct += !copy;
  }
  ASSERT_LE(distinct, n);
  while (!f.begin_step(run.log.steps[k])) ++k;
  EXPECT_EQ(f.pending_moves(), distinct);
  for (size_t g = 0; g < f.pending_moves(); ++g) f.move(g);
  f.end_step();
  EXPECT_EQ(f.stats().shared_starts, n - 1 + drawn.size() - distinct);
  EXPECT_EQ(f.stats().particle_moves, 2 * n + 1 * drawn.size());
}

TEST(GridRbpf, BeginStepTwiceIsAnError) {
  const auto run = loop_run(14);
  GridRbpf f(small_filter(1));
  size_t k = 0;
  while (k < run.log.steps.size() && !f.begin_step(run.log.steps[k])) ++k;
  ASSERT_LT(k, run.log.steps.size());
  EXPECT_THROW(f.begin_step(run.log.steps[k + 1]), Error);
}

TEST(GridRbpf, ParticlesShareMapMemory) {
  // Down a long corridor, each scan (8 m range) touches a short stretch of
  // the map: the particles' maps differ only there.
  const auto run = testing_sim::simulate({{1, 1.5, 0}, {148, 1.5, 0}}, 0.7, 13, 0.05,
                                         testing_sim::corridor_world(150.0), 8.0);
  RbpfOptions o = small_filter(2);
  o.particles = 30;
  // Resampling at every step: the particles then share all history but the
  // last step's changes.
  o.resample_threshold = 1.0;
  GridRbpf f(o);
  for (const auto& st : run.log.steps) f.process(st);
  size_t unshared = 0;
  for (const auto& p : f.particles()) unshared += p.map.tile_bytes();
  // Distinct tiles are far fewer than 30 private maps would need.
  EXPECT_LT(f.map_memory_bytes() * 4, unshared);
}

TEST(GridRbpf, OdometryProposalStillRuns) {
  const auto run = loop_run(14);
  RbpfOptions o = small_filter(1);
  o.proposal = ProposalKind::kOdometry;
  GridRbpf f(o);
  for (const auto& st : run.log.steps) f.process(st);
  EXPECT_EQ(f.stats().odometry_fallbacks, (run.log.steps.size() - 1) * 10);
  // Every particle-step fell back: the counts agree.
  EXPECT_EQ(f.stats().particle_moves, f.stats().odometry_fallbacks);
}

TEST(GridRbpf, NewAreaAndReloadInterface) {
  const auto run = loop_run(15);
  GridRbpf f(small_filter(1));
  for (size_t i = 0; i < 20; ++i) f.process(run.log.steps[i]);
  const grid::OccupancyGrid first_area = f.best().map;
  const Pose2D before = f.best().pose;
  std::vector<Pose2D> estimated;
  for (const auto& p : f.particles()) estimated.push_back(p.estimates.back());
  const auto origins = f.start_new_area();
  ASSERT_EQ(origins.size(), f.particles().size());
  for (size_t i = 0; i < origins.size(); ++i) {
    const Particle& p = f.particles()[i];
    EXPECT_EQ(p.pose.x, 0.0);
    EXPECT_EQ(p.path.size(), 1u);
    EXPECT_LT(p.map.tile_count(), first_area.tile_count() + 1);
    // The estimates go on from where they were, seen from the new origin.
    ASSERT_EQ(p.estimates.size(), 1u);
    EXPECT_LT((origins[i] + p.estimates[0] - estimated[i]).norm(), 1e-12);
  }
  EXPECT_NEAR(origins[f.best_index()].x, before.x, 1e-12);
  f.load_area(first_area, {before});
  for (const auto& p : f.particles()) {
    EXPECT_EQ(p.pose.x, before.x);
    EXPECT_EQ(p.map.tile_count(), first_area.tile_count());
  }
  // Keeps working in the reloaded map.
  for (size_t i = 20; i < 30; ++i) f.process(run.log.steps[i]);
  EXPECT_EQ(f.best().path.size(), 11u);
}

TEST(GridRbpf, AKnownAreaReenteredAtItsEdgeTakesTheLastScanWhereItCannotTrack) {
  // Down a corridor with 8 m scans: the map of the first five steps reaches
  // about 12 m; twenty steps later the robot sees 11-27 m. Re-entering that
  // map there (as a closure at an area's edge does), the particles find
  // next to nothing to match unless the last scan comes with them.
  const auto run = testing_sim::simulate({{1, 1.5, 0}, {45, 1.5, 0}}, 0.7, 13, 0.05,
                                         testing_sim::corridor_world(60.0), 8.0);
  ASSERT_GT(run.log.steps.size(), 45u);
  GridRbpf f(small_filter(1));
  for (size_t i = 0; i <= 5; ++i) f.process(run.log.steps[i]);
  const grid::OccupancyGrid known = f.best().map;
  const size_t now = 25;
  for (size_t i = 6; i <= now; ++i) f.process(run.log.steps[i]);

  // Where the map tracks the robot (its own map, here), it is taken as it is.
  const Pose2D at = f.best().pose;  // the known map shares the filter's frame
  GridRbpf same = f;
  const grid::OccupancyGrid own = f.best().map;
  same.load_area(own, {at}, &at);
  EXPECT_EQ(same.best().map.tile_count(), own.tile_count());
  grid::CellIndex lo, hi;
  ASSERT_TRUE(own.bounds(&lo, &hi));
  for (int y = lo.y; y <= hi.y; ++y)
    for (int x = lo.x; x <= hi.x; ++x)
      ASSERT_EQ(same.best().map.logodds({x, y}), own.logodds({x, y}));

  // Where it does not, the last scan fills what it never observed, and only
  // that: every cell the known map observed keeps its value.
  GridRbpf bare = f;
  f.load_area(known, {at}, &at);
  bare.load_area(known, {at});
  EXPECT_GT(f.best().map.tile_count(), known.tile_count());
  EXPECT_EQ(bare.best().map.tile_count(), known.tile_count());
  ASSERT_TRUE(known.bounds(&lo, &hi));
  for (int y = lo.y; y <= hi.y; ++y)
    for (int x = lo.x; x <= hi.x; ++x)
      if (known.logodds({x, y}) != 0) {
        ASSERT_EQ(f.best().map.logodds({x, y}), known.logodds({x, y}));
      }

  const size_t filled_fallbacks = f.stats().odometry_fallbacks;
  const size_t bare_fallbacks = bare.stats().odometry_fallbacks;
  for (size_t i = now + 1; i <= now + 15; ++i) {
    f.process(run.log.steps[i]);
    bare.process(run.log.steps[i]);
  }
  // With the scan, every particle matched every scan; bare, the first scans
  // after the re-entry matched too little and fell back on the odometry.
  EXPECT_EQ(f.stats().odometry_fallbacks, filled_fallbacks);
  EXPECT_GT(bare.stats().odometry_fallbacks, bare_fallbacks);
  // Along the corridor the position drifts whichever way (the walls do not
  // fix it); the heading, which the walls do fix, stays as good as it was
  // at the re-entry.
  const Pose2D truth = run.truth[now + 15];
  const Pose2D est = run.truth.front() + f.best().pose;
  const Pose2D then = run.truth.front() + at;
  EXPECT_LE(std::fabs(wrap_angle(est.theta - truth.theta)),
            std::fabs(wrap_angle(then.theta - run.truth[now].theta)) + 0.01);
}

TEST(GridRbpf, ResizeAndRestart) {
  const auto run = loop_run(15);
  GridRbpf f(small_filter(1));
  for (size_t i = 0; i < 20; ++i) f.process(run.log.steps[i]);
  f.resize(4);
  ASSERT_EQ(f.particles().size(), 4u);
  for (double w : f.weights()) EXPECT_DOUBLE_EQ(w, 0.25);
  f.resize(12);
  ASSERT_EQ(f.particles().size(), 12u);
  for (size_t i = 20; i < 30; ++i) f.process(run.log.steps[i]);
  EXPECT_EQ(f.particles().size(), 12u);  // resampling keeps the new count
  EXPECT_EQ(f.best().path.size(), 30u);
  EXPECT_THROW(f.resize(0), Error);

  // Restart: every particle (the configured count) at the pose, in the map.
  const grid::OccupancyGrid map = f.best().map;
  const Pose2D at = f.best().pose;
  f.restart(map, at);
  ASSERT_EQ(f.particles().size(), 10u);
  for (const auto& p : f.particles()) {
    EXPECT_EQ(p.pose.x, at.x);
    EXPECT_EQ(p.path.size(), 1u);
    EXPECT_EQ(p.map.tile_count(), map.tile_count());
  }
  for (size_t i = 30; i < 40; ++i) f.process(run.log.steps[i]);
  EXPECT_LT((f.best().pose - run.truth[39]).norm(), (at - run.truth[29]).norm() + 0.5);
}

}  // namespace
}  // namespace hmt::metric_slam
