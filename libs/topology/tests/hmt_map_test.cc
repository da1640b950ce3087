#include "hmt/topology/hmt_map.h"

#include <gtest/gtest.h>

#include "test_util.h"

#include <Eigen/Dense>
#include <cmath>
#include <stdexcept>

namespace hmt::topology {
namespace {

using testing_util::cov_of;
using testing_util::diag;
using testing_util::vec;


Eigen::Matrix3d correlated() {
  Eigen::Matrix3d c;
  c << 0.04, 0.01, 0.002,  //
      0.01, 0.09, -0.003,  //
      0.002, -0.003, 0.0025;
  return c;
}


HmtMap three_areas() {
  HmtMap m;
  m.add_area(0);
  m.add_area(1, {0, Pose2D(4, 0, 0.5), 120, 12.0});
  m.add_area(2, {1, Pose2D(3, 1, -0.2), 300, 30.0});
  return m;
}

TEST(HmtMap, AreasAreOrderedAndValidated) {
  HmtMap m;
  EXPECT_EQ(m.next_area_id(), 0u);
  m.add_area(5);
  m.add_area(2, {5, Pose2D(1, 2, 3), 7, 0.7});
  EXPECT_EQ(m.area_ids(), (std::vector<AreaId>{2, 5}));
  EXPECT_EQ(m.next_area_id(), 6u);
  EXPECT_EQ(m.area(2).frame.parent, 5u);
  EXPECT_EQ(m.area(2).frame.created_step, 7u);
  EXPECT_EQ(m.area(5).frame.parent, kNoArea);
  EXPECT_FALSE(m.area(5).map);
  EXPECT_THROW(m.add_area(5), std::invalid_argument);  // exists
  EXPECT_THROW(m.add_area(9, {8, Pose2D(), 0, 0}),
               std::invalid_argument);  // no parent
  EXPECT_THROW(m.add_area(kNoArea), std::invalid_argument);
  EXPECT_THROW(m.area(3), std::out_of_range);
  EXPECT_THROW(m.add_keyframe(3, Keyframe{}), std::out_of_range);
}

TEST(HmtMap, ArcMeasurementsFuseInClosedForm) {
  HmtMap m = three_areas();
  const PoseGaussian z1(Pose2D(4.0, 0.1, 0.5), correlated());
  const PoseGaussian z2(Pose2D(4.2, -0.1, 0.45), diag(0.1, 0.1, 0.02));
  const Arc& first = m.add_arc_measurement(0, 1, z1);
  EXPECT_EQ(first.measurements, 1u);
  EXPECT_LT((first.pose.cov - z1.cov).cwiseAbs().maxCoeff(), 1e-15);
  const Arc& second = m.add_arc_measurement(0, 1, z2);
  EXPECT_EQ(second.measurements, 2u);
  const PoseGaussian expected = fuse(z1, z2);
  EXPECT_LT((vec(second.pose.mean) - vec(expected.mean)).cwiseAbs().maxCoeff(),
            1e-12);
  EXPECT_LT((second.pose.cov - expected.cov).cwiseAbs().maxCoeff(), 1e-15);
  // Each fusion makes the arc more certain.
  EXPECT_LT(second.pose.cov.determinant(), z1.cov.determinant());
  EXPECT_LT(second.pose.cov.determinant(), z2.cov.determinant());
  EXPECT_EQ(m.arcs().size(), 1u);
}

TEST(HmtMap, ArcsAnswerInBothDirections) {
  HmtMap m = three_areas();
  const PoseGaussian z(Pose2D(3.0, 1.0, 2.9), correlated());
  m.add_arc_measurement(1, 2, z);
  ASSERT_TRUE(m.has_arc(2, 1));
  const PoseGaussian fwd = m.arc(1, 2), back = m.arc(2, 1);
  const PoseGaussian inv = inverse(z);
  EXPECT_LT((vec(back.mean) - vec(inv.mean)).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_LT((back.cov - inv.cov).cwiseAbs().maxCoeff(), 1e-15);
  // Composing there and back gives the identity mean.
  const Pose2D round = fwd.mean + back.mean;
  EXPECT_NEAR(round.x, 0, 1e-12);
  EXPECT_NEAR(round.y, 0, 1e-12);
  EXPECT_NEAR(round.theta, 0, 1e-12);
  EXPECT_THROW(m.arc(0, 2), std::out_of_range);
  EXPECT_EQ(m.find_arc(2, 1), m.find_arc(1, 2));
  EXPECT_EQ(m.find_arc(2, 1)->from, 1u);
  EXPECT_EQ(m.neighbours(1), (std::vector<AreaId>{2}));
  EXPECT_EQ(m.neighbours(2), (std::vector<AreaId>{1}));
  EXPECT_TRUE(m.neighbours(0).empty());
}

TEST(HmtMap, ReverseMeasurementFusesLikeTheForwardOne) {
  // The same crossing reported as 2 -> 1 (the inverse Gaussian) counts as a
  // second equal measurement of 1 -> 2: the covariance halves.
  HmtMap m = three_areas();
  const PoseGaussian z(Pose2D(3.0, 1.0, -0.2), correlated());
  m.add_arc_measurement(1, 2, z);
  const Arc& arc = m.add_arc_measurement(2, 1, inverse(z));
  EXPECT_EQ(arc.measurements, 2u);
  EXPECT_LT((vec(arc.pose.mean) - vec(z.mean)).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_LT((arc.pose.cov - 0.5 * z.cov).cwiseAbs().maxCoeff(), 1e-14);
  // First measured backwards: stored canonically, answered forwards.
  HmtMap n = three_areas();
  n.add_arc_measurement(2, 1, inverse(z));
  EXPECT_LT((vec(n.arc(1, 2).mean) - vec(z.mean)).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_LT((n.arc(1, 2).cov - z.cov).cwiseAbs().maxCoeff(), 1e-14);
}

TEST(HmtMap, ArcsRequireRealPositiveDefiniteCovariances) {
  HmtMap m = three_areas();
  EXPECT_THROW(m.add_arc_measurement(0, 1, PoseGaussian(Pose2D(1, 0, 0))),
               std::invalid_argument);  // zero covariance
  Eigen::Matrix3d indefinite = diag(0.1, 0.1, 0.1);
  indefinite(0, 1) = indefinite(1, 0) = 0.05;  // |rho| > 1
  EXPECT_THROW(
      m.add_arc_measurement(0, 1, PoseGaussian(Pose2D(1, 0, 0), indefinite)),
      std::invalid_argument);
  EXPECT_THROW(
      m.add_arc_measurement(0, 0, PoseGaussian(Pose2D(), diag(1, 1, 1))),
      std::invalid_argument);
  EXPECT_THROW(
      m.add_arc_measurement(0, 7, PoseGaussian(Pose2D(), diag(1, 1, 1))),
      std::invalid_argument);
  EXPECT_THROW(m.add_arc_measurement(
                   0, 1, PoseGaussian(Pose2D(NAN, 0, 0), diag(1, 1, 1))),
               std::invalid_argument);
  EXPECT_TRUE(m.arcs().empty());
  Arc a;
  a.from = 0;
  a.to = 1;
  a.pose = PoseGaussian(Pose2D(1, 0, 0), diag(1, 1, 1));
  a.measurements = 0;
  EXPECT_THROW(m.set_arc(a), std::invalid_argument);
  a.measurements = 3;
  m.set_arc(a);
  EXPECT_EQ(m.find_arc(0, 1)->measurements, 3u);
}

TEST(HmtMap, CopiesShareAreasUntilOneIsChanged) {
  HmtMap a = three_areas();
  Keyframe kf;
  kf.pose = Pose2D(1, 2, 0.3);
  kf.scan.ranges = {1.0f, 2.0f};
  kf.scan.valid = {1, 0};
  a.add_keyframe(1, kf);
  HmtMap b = a;
  EXPECT_EQ(&a.area(1), &b.area(1));  // shared, not copied
  b.add_keyframe(1, kf);
  EXPECT_NE(&a.area(1), &b.area(1));
  EXPECT_EQ(a.area(1).keyframes.size(), 1u);
  EXPECT_EQ(b.area(1).keyframes.size(), 2u);
  EXPECT_EQ(&a.area(0), &b.area(0));  // untouched areas stay shared
  // A scan whose flags do not match its ranges is refused.
  kf.scan.valid.pop_back();
  EXPECT_THROW(a.add_keyframe(1, kf), std::invalid_argument);
}

TEST(HmtMap, FindsAKeyframeNearAPoseWithinBothDistanceAndAngle) {
  HmtMap m = three_areas();
  Keyframe kf;
  kf.pose = Pose2D(1, 2, 3.0);
  kf.scan.ranges = {1.0f};
  kf.scan.valid = {1};
  m.add_keyframe(1, kf);
  EXPECT_TRUE(m.has_keyframe_near(1, Pose2D(1.3, 2.3, 3.0), 0.5, 0.5));
  EXPECT_FALSE(m.has_keyframe_near(1, Pose2D(1.3, 2.3, 3.0), 0.4, 0.5));  // 0.42 m away
  // Headings compare across +-pi: 3.0 and -3.1 are 0.18 rad apart.
  EXPECT_TRUE(m.has_keyframe_near(1, Pose2D(1, 2, -3.1), 0.5, 0.2));
  EXPECT_FALSE(m.has_keyframe_near(1, Pose2D(1, 2, -3.1), 0.5, 0.15));
  EXPECT_FALSE(m.has_keyframe_near(0, Pose2D(1, 2, 3.0), 0.5, 0.5));  // another area
  EXPECT_THROW(m.has_keyframe_near(7, Pose2D(), 0.5, 0.5), std::out_of_range);
}

TEST(HmtMap, ArchivedMapIsASharedImmutableSnapshot) {
  HmtMap m = three_areas();
  grid::OccupancyGrid live(0.05);
  for (int i = -100; i < 100; ++i) live.mutable_logodds({i, 2 * i}) = 30;
  m.archive_map(0, live);
  const grid::OccupancyGrid& snap = *m.area(0).map;
  // The snapshot points at the very same tiles as the live grid.
  EXPECT_EQ(snap.tile_of({10, 20}), live.tile_of({10, 20}));
  EXPECT_EQ(snap.tile_count(), live.tile_count());
  // The live grid keeps mapping: it clones the tile it writes, the snapshot
  // does not change.
  live.mutable_logodds({10, 20}) = -40;
  EXPECT_NE(snap.tile_of({10, 20}), live.tile_of({10, 20}));
  EXPECT_EQ(snap.logodds({10, 20}), 30);
  EXPECT_EQ(live.logodds({10, 20}), -40);
  EXPECT_EQ(snap.tile_of({-99, -198}), live.tile_of({-99, -198}));
  // Copies of the HMT map share the snapshot.
  const HmtMap copy = m;
  EXPECT_EQ(copy.area(0).map.get(), &snap);
}

}  // namespace
}  // namespace hmt::topology
