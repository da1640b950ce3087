#include "hmt/tlca/acceptance.h"

#include <gtest/gtest.h>

#include <memory>

#include "../../metric_slam/tests/sim_world.h"
#include "hmt/grid/scan_insertion.h"

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

}  // namespace
}  // namespace hmt::tlca
