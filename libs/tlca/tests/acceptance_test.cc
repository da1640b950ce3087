#include "hmt/tlca/acceptance.h"

#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <memory>

#include "../../metric_slam/tests/sim_world.h"
#include "hmt/common/error.h"
#include "hmt/grid/scan_insertion.h"
#include "hmt/topology/shortest_paths.h"

namespace hmt::tlca {
namespace {

using topology::PoseGaussian;

Eigen::Matrix3d diag(double sxy, double sth) {
  return Eigen::Vector3d(sxy * sxy, sxy * sxy, sth * sth).asDiagonal();
}

TEST(Dominant, ProbabilityPolicy) {
  TlcaOptions o;
  o.accept_probability = 0.9;
  EXPECT_EQ(dominant({1.0}, o), std::optional<size_t>(0));
  EXPECT_EQ(dominant({0.5, 0.5}, o), std::nullopt);
  EXPECT_EQ(dominant({0.05, 0.95}, o), std::optional<size_t>(1));
  EXPECT_EQ(dominant({}, o), std::nullopt);
}

TEST(Dominant, UniquePolicyWaitsForTheLastOne) {
  TlcaOptions o;
  o.policy = AcceptancePolicy::kUnique;
  EXPECT_EQ(dominant({0.001, 0.999}, o), std::nullopt);
  EXPECT_EQ(dominant({1.0}, o), std::optional<size_t>(0));
}

// The office seen in two areas: area 1's frame is the world, area 2's frame
// is at world `origin2`; both map the left part of the office.
struct TwoViews {
  topology::HmtMap map;
  Pose2D origin2{1.0, 0.5, 0.15};
  TwoViews() {
    const auto world = testing_sim::office_world();
    auto g1 = std::make_shared<grid::OccupancyGrid>(0.05);
    auto g2 = std::make_shared<grid::OccupancyGrid>(0.05);
    for (const Pose2D p : {Pose2D(2, 2, 0), Pose2D(4, 4, 1.5), Pose2D(6, 8, 3.0)}) {
      const LaserScan s = testing_sim::cast_scan(world, p, 361, M_PI, 30, nullptr, 0);
      grid::insert_scan(*g1, p, s, {});
    }
    for (const Pose2D p : {Pose2D(3, 3, 0.5), Pose2D(5, 5, 2.0), Pose2D(2, 8, -1.5)}) {
      const LaserScan s = testing_sim::cast_scan(world, p, 361, M_PI, 30, nullptr, 0);
      grid::insert_scan(*g2, p - origin2, s, {});
    }
    map.add_area(1);
    map.add_area(2);
    map.set_map(1, g1);
    map.set_map(2, g2);
  }
};

TEST(AcceptClosure, FineAlignmentCorrectsTheArc) {
  TwoViews v;
  ClosureRecord rec;
  rec.from = 2;  // the robot left area 2 and closed into area 1
  rec.to = 1;
  // Area 1's frame in area 2's frame, off by 0.12 m and 0.04 rad.
  rec.measurement = PoseGaussian(v.origin2.inverse() + Pose2D(0.1, -0.07, 0.04), diag(0.1, 0.05));
  v.map.add_arc_measurement(2, 1, rec.measurement);
  const ClosureReport r = accept_closure(v.map, rec, TlcaOptions{});
  ASSERT_TRUE(r.aligned) << r.reason;
  const PoseGaussian arc = v.map.arc(2, 1);
  const Pose2D err = arc.mean - v.origin2.inverse();
  EXPECT_LT(err.norm(), 0.03);
  EXPECT_LT(std::fabs(err.theta), 0.01);
  EXPECT_GT(r.correction_m, 0.05);
  EXPECT_EQ(v.map.find_arc(1, 2)->measurements, 1u);
  EXPECT_TRUE(topology::is_positive_definite(arc.cov));
}

TEST(AcceptClosure, FusesWithTheArcFromEarlierCrossings) {
  TwoViews v;
  topology::Arc before;
  before.from = 1;
  before.to = 2;
  before.pose = PoseGaussian(v.origin2, diag(0.05, 0.02));
  before.measurements = 3;
  ClosureRecord rec;
  rec.from = 2;
  rec.to = 1;
  rec.arc_before = before;
  rec.measurement = PoseGaussian(v.origin2.inverse(), diag(0.1, 0.05));
  TlcaOptions o;
  o.fine_alignment = false;  // fuse TSBI's measurement as it is
  const ClosureReport r = accept_closure(v.map, rec, o);
  EXPECT_FALSE(r.aligned);
  EXPECT_EQ(r.reason, "fine alignment disabled");
  const topology::Arc* a = v.map.find_arc(1, 2);
  ASSERT_NE(a, nullptr);
  EXPECT_EQ(a->measurements, 4u);
  // Fusion shrinks the covariance below both inputs.
  EXPECT_LT(a->pose.cov(0, 0), before.pose.cov(0, 0));
  EXPECT_NEAR(a->pose.mean.x, v.origin2.x, 1e-6);
}

TEST(AcceptClosure, WithoutMapsKeepsTheMeasurement) {
  topology::HmtMap map;
  map.add_area(1);
  map.add_area(2);
  ClosureRecord rec;
  rec.from = 2;
  rec.to = 1;
  rec.measurement = PoseGaussian(Pose2D(1, 2, 0.3), diag(0.1, 0.05));
  const ClosureReport r = accept_closure(map, rec, TlcaOptions{});
  EXPECT_FALSE(r.aligned);
  EXPECT_NEAR(map.arc(2, 1).mean.x, 1.0, 1e-12);
}

// A corridor walked area by area: n areas in a row, 4 m apart, each created
// from the one before (crossing covariances of 0.1 m, 0.02 rad), no grids
// (so only the loop check (b) applies). The robot then comes back from the
// last area into area 1 and TSBI puts that closure into the map, as the
// snapshot TLCA checks holds it.
struct Corridor {
  topology::HmtMap map;
  std::vector<Pose2D> truth;
  explicit Corridor(topology::AreaId n) {
    for (topology::AreaId i = 1; i <= n; ++i) {
      topology::ReferenceFrame f;
      if (i > 1) f.parent = i - 1;
      map.add_area(i, f);
      truth.emplace_back(4.0 * (i - 1), 0.0, 0.0);
      if (i > 1) map.add_arc_measurement(i - 1, i, PoseGaussian(truth[i - 1] - truth[i - 2], diag(0.1, 0.02)));
    }
  }
  ClosureRecord closure_into_1(const Pose2D& error) {
    ClosureRecord rec;
    rec.from = static_cast<topology::AreaId>(truth.size());
    rec.to = 1;
    rec.step = 500;
    rec.measurement = PoseGaussian((truth.front() - truth.back()) + error, diag(0.03, 0.005));
    map.add_arc_measurement(rec.from, rec.to, rec.measurement);
    return rec;
  }
};

// Squared Mahalanobis distance of the stored arc from..to from the other
// path between its ends, as check (b) computes it.
double arc_vs_path(const topology::HmtMap& map, const ClosureRecord& rec, const Pose2D& path_mean,
                   const Eigen::Matrix3d& path_cov) {
  const PoseGaussian arc = map.arc(rec.from, rec.to);
  const Eigen::Vector3d d = topology::difference(arc.mean, path_mean);
  return d.dot((arc.cov + path_cov).ldlt().solve(d));
}

TEST(ClosureConsistency, AClosureThatAgreesWithTheArcsIsFused) {
  Corridor c(4);
  const ClosureRecord rec = c.closure_into_1(Pose2D(0.05, -0.03, 0.01));
  const ClosureReport r = accept_closure(c.map, rec, TlcaOptions{});
  EXPECT_TRUE(r.consistent) << r.reason;
  EXPECT_EQ(r.reason, "an area has no archived map");
  EXPECT_EQ(r.loop_hops, 3u);
  EXPECT_GT(r.loop_chi2, 0.0);
  EXPECT_LT(r.loop_chi2, TlcaOptions{}.consistency_chi2);
  // Fused as measured.
  EXPECT_EQ(r.used.cov, rec.measurement.cov);
  EXPECT_LT((c.map.arc(4, 1).cov - rec.measurement.cov).cwiseAbs().maxCoeff(), 1e-15);
}

TEST(ClosureConsistency, AClosureOffTheArcsIsInflatedAndCannotBendTheMap) {
  // Area 4 taken for area 1 with its pose 3 m, 2 m and 0.5 rad off: a
  // look-alike room, measured with a fine alignment's small covariance.
  Corridor c(4);
  const PoseGaussian path = topology::compose_path(c.map, {4, 3, 2, 1});
  const ClosureRecord rec = c.closure_into_1(Pose2D(3.0, 2.0, 0.5));
  const ClosureReport r = accept_closure(c.map, rec, TlcaOptions{});
  EXPECT_FALSE(r.consistent);
  EXPECT_NE(r.reason.find("inconsistent with the other path of 3 arcs"), std::string::npos)
      << r.reason;
  EXPECT_NE(r.reason.find("fused with its covariance inflated"), std::string::npos) << r.reason;
  EXPECT_EQ(r.loop_hops, 3u);
  EXPECT_GT(r.loop_chi2, 100.0);
  // The arc keeps the crossing (the map stays connected the way the robot
  // went) with the measured mean, but agrees with the rest of the map...
  ASSERT_TRUE(c.map.has_arc(4, 1));
  EXPECT_LT(topology::difference(c.map.arc(4, 1).mean, rec.measurement.mean).norm(), 1e-12);
  EXPECT_LT(arc_vs_path(c.map, rec, path.mean, path.cov), 1.0);
  // ... and the map's composed poses go round it: from 4, area 1 is
  // reached through the chain, not through the inflated arc.
  EXPECT_EQ(topology::shortest_paths(c.map, 4).path_to(1),
            (std::vector<topology::AreaId>{4, 3, 2, 1}));
  // Without the check the same closure would be fused as measured.
  Corridor plain(4);
  TlcaOptions off;
  off.consistency_check = false;
  const ClosureReport p = accept_closure(plain.map, plain.closure_into_1(Pose2D(3.0, 2.0, 0.5)), off);
  EXPECT_TRUE(p.consistent);
  EXPECT_EQ(p.loop_hops, 0u);
  EXPECT_LT((plain.map.arc(4, 1).cov - rec.measurement.cov).cwiseAbs().maxCoeff(), 1e-15);
}

TEST(ClosureConsistency, TheGateGrowsWithTheLoop) {
  // The same 1.3 m / 0.08 rad discrepancy: beyond the uncertainty of two
  // crossings, within that of twenty (the drift of a long loop).
  const Pose2D error(1.0, 0.8, 0.08);
  Corridor short_loop(3), long_loop(21);
  const ClosureReport s =
      accept_closure(short_loop.map, short_loop.closure_into_1(error), TlcaOptions{});
  const ClosureReport l =
      accept_closure(long_loop.map, long_loop.closure_into_1(error), TlcaOptions{});
  EXPECT_FALSE(s.consistent) << s.loop_chi2;
  EXPECT_TRUE(l.consistent) << l.loop_chi2 << " " << l.reason;
  EXPECT_EQ(s.loop_hops, 2u);
  EXPECT_EQ(l.loop_hops, 20u);
}

TEST(ClosureConsistency, ChecksAgainstTheArcFromEarlierCrossings) {
  // A closure through the areas' own crossing: the other path is what the
  // arc held before, and an inconsistent closure leaves it nearly as it was.
  Corridor c(2);
  const PoseGaussian before = c.map.arc(1, 2);
  ClosureRecord rec;
  rec.from = 2;
  rec.to = 1;
  rec.arc_before = *c.map.find_arc(1, 2);
  rec.measurement = PoseGaussian(Pose2D(-4.0, 0.0, 0.0) + Pose2D(2.0, 1.5, 0.4), diag(0.03, 0.005));
  c.map.add_arc_measurement(2, 1, rec.measurement);
  const ClosureReport r = accept_closure(c.map, rec, TlcaOptions{});
  EXPECT_FALSE(r.consistent);
  EXPECT_EQ(r.loop_hops, 1u);
  const topology::Arc* a = c.map.find_arc(1, 2);
  ASSERT_NE(a, nullptr);
  EXPECT_EQ(a->measurements, 2u);
  EXPECT_LT(topology::difference(a->pose.mean, before.mean).head<2>().norm(), 0.1);
  EXPECT_LT(std::fabs(topology::difference(a->pose.mean, before.mean)(2)), 0.02);
}

TEST(ClosureConsistency, TheFloorAllowsForTheAreaMapsOwnError) {
  // Two fine alignments of the same pair of areas, each claiming 2 mm and
  // 1 mrad, 8.7 cm apart (as on the Malaga log): the grids' Hessian leaves
  // out the error of the area maps themselves, which the floor stands for.
  auto run = [](double floor_xy, double floor_theta) {
    Corridor c(2);
    topology::Arc before;
    before.from = 1;
    before.to = 2;
    before.pose = PoseGaussian(Pose2D(4.0, 0.0, 0.0), diag(0.002, 0.001));
    before.measurements = 2;
    c.map.set_arc(before);
    ClosureRecord rec;
    rec.from = 2;
    rec.to = 1;
    rec.arc_before = before;
    rec.measurement = PoseGaussian(Pose2D(-4.0, 0.0, 0.0) + Pose2D(-0.028, 0.082, 0.0007),
                                   diag(0.002, 0.001));
    c.map.add_arc_measurement(2, 1, rec.measurement);
    TlcaOptions o;
    o.consistency_floor_xy = floor_xy;
    o.consistency_floor_theta = floor_theta;
    return accept_closure(c.map, rec, o);
  };
  const ClosureReport with_floor = run(0.05, 0.02);
  EXPECT_TRUE(with_floor.consistent) << with_floor.reason;
  EXPECT_LT(with_floor.loop_chi2, 4.0);
  const ClosureReport without = run(0.0, 0.0);
  EXPECT_FALSE(without.consistent);
  EXPECT_GT(without.loop_chi2, 100.0);
}

TEST(ClosureConsistency, GridsThatDoNotOverlapFailAlone) {
  // No other path (two areas, the closure their only arc): only check (a).
  // Area 2 is a corridor elsewhere taken for the office of area 1: aligned
  // from TSBI's guess, few of its walls meet the office's. The closure
  // closes no loop, so it is kept as measured, and said to be inconsistent.
  TwoViews v;
  auto corridor = std::make_shared<grid::OccupancyGrid>(0.05);
  const auto world = testing_sim::corridor_world(20.0);
  for (const Pose2D p : {Pose2D(4, 1.5, 0), Pose2D(9, 1.5, 0), Pose2D(14, 1.5, M_PI)}) {
    const LaserScan s = testing_sim::cast_scan(world, p, 361, M_PI, 30, nullptr, 0);
    grid::insert_scan(*corridor, p, s, {});
  }
  v.map.set_map(2, corridor);
  ClosureRecord rec;
  rec.from = 2;
  rec.to = 1;
  rec.measurement = PoseGaussian(Pose2D(-3.0, -2.0, 0.0), diag(0.3, 0.1));
  v.map.add_arc_measurement(2, 1, rec.measurement);
  const ClosureReport r = accept_closure(v.map, rec, TlcaOptions{});
  EXPECT_FALSE(r.aligned);
  EXPECT_FALSE(r.consistent);
  EXPECT_NE(r.reason.find("the grids do not overlap at the closure"), std::string::npos)
      << r.reason;
  EXPECT_NE(r.reason.find("fused as measured: it closes no loop"), std::string::npos) << r.reason;
  EXPECT_EQ(r.loop_hops, 0u);
  EXPECT_LT((v.map.arc(2, 1).cov - rec.measurement.cov).cwiseAbs().maxCoeff(), 1e-15);
  // The two views of the office pass (a): aligned, consistent.
  TwoViews w;
  rec.measurement = PoseGaussian(w.origin2.inverse() + Pose2D(0.1, -0.07, 0.04), diag(0.1, 0.05));
  w.map.add_arc_measurement(2, 1, rec.measurement);
  const ClosureReport ok = accept_closure(w.map, rec, TlcaOptions{});
  EXPECT_TRUE(ok.aligned) << ok.reason;
  EXPECT_TRUE(ok.consistent) << ok.reason;
  EXPECT_EQ(ok.reason, "");
}

TEST(TlcaOptions, ConsistencyKeysAreReadAndChecked) {
  Config cfg = Config::from_string(
      "[tlca]\nconsistency_check = false\nconsistency_chi2 = 12.5\n"
      "consistency_floor_xy = 0\nconsistency_floor_theta = 0.1\n",
      "test");
  TlcaOptions o;
  o.load(cfg);
  EXPECT_FALSE(o.consistency_check);
  EXPECT_EQ(o.consistency_chi2, 12.5);
  EXPECT_EQ(o.consistency_floor_xy, 0.0);
  EXPECT_EQ(o.consistency_floor_theta, 0.1);
  for (const char* bad : {"consistency_chi2 = 0", "consistency_chi2 = -3", "consistency_chi2 = nan",
                          "consistency_chi2 = inf", "consistency_check = maybe",
                          "consistency_floor_xy = -0.01", "consistency_floor_theta = nan"}) {
    SCOPED_TRACE(bad);
    Config c = Config::from_string(std::string("[tlca]\n") + bad + "\n", "test");
    TlcaOptions t;
    EXPECT_THROW(t.load(c), ConfigError);
  }
}

}  // namespace
}  // namespace hmt::tlca
