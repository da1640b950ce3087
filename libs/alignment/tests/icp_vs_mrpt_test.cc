// Our classic ICP (icp.h) against MRPT's CICP (icpClassic), which the
// registration step used before, with the options grid_alignment.cc used to
// give it, on the grids of the alignment tests and on real grids: the
// Edmonton log at its reference poses, two views of the same place.
// MRPT works in single precision (float points, float sums in its closed-form
// fit, whose rounding makes the pose jitter by up to ~1e-4 rad from one
// iteration to the next), ours in double; both stop at a fixed point of the
// pairing, which on noisy grids is a millimetre wide. They agree within 2 mm
// and 0.2 mrad (here: 0.003 to 1.3 mm, 0.1 to 92 microradians).
#include <gtest/gtest.h>
#include <mrpt/maps/CSimplePointsMap.h>
#include <mrpt/poses/CPose2D.h>
#include <mrpt/poses/CPosePDF.h>
#include <mrpt/slam/CICP.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "hmt/alignment/grid_alignment.h"
#include "hmt/alignment/icp.h"
#include "hmt/grid/scan_insertion.h"
#include "hmt/grouping/scan_poses.h"
#include "hmt/io/log_reader.h"
#include "synthetic_rooms.h"

namespace hmt::alignment {
namespace {

using testing::crop;
using testing::room_tour_a;
using testing::room_tour_b;
using testing::room_world;
using testing::scanned_grid;

struct MrptResult {
  Pose2D pose;
  int iterations = 0;
};

MrptResult mrpt_icp(const std::vector<Point2D>& moving, const std::vector<Point2D>& fixed,
                    const Pose2D& start, const AlignmentOptions& opt) {
  mrpt::maps::CSimplePointsMap fixed_map, moving_map;
  for (const Point2D& p : fixed)
    fixed_map.insertPoint(static_cast<float>(p.x), static_cast<float>(p.y), 0.0f);
  for (const Point2D& p : moving)
    moving_map.insertPoint(static_cast<float>(p.x), static_cast<float>(p.y), 0.0f);
  mrpt::slam::CICP icp;
  auto& o = icp.options;
  o.ICP_algorithm = mrpt::slam::icpClassic;
  o.maxIterations = static_cast<unsigned>(opt.icp_max_iterations);
  o.thresholdDist = opt.icp_threshold_start;
  o.thresholdAng = opt.icp_threshold_angular;
  o.ALFA = opt.icp_threshold_decay;
  o.smallestThresholdDist = opt.icp_threshold_end;
  o.onlyUniqueRobust = false;
  o.corresponding_points_decimation = 1;
  o.doRANSAC = false;
  o.skip_cov_calculation = true;
  o.skip_quality_calculation = true;
  mrpt::slam::CICP::TReturnInfo info;
  const mrpt::poses::CPosePDF::Ptr pdf = icp.Align(
      &fixed_map, &moving_map, mrpt::poses::CPose2D(start.x, start.y, start.theta), info);
  const mrpt::poses::CPose2D m = pdf->getMeanVal();
  return {{m.x(), m.y(), wrap_angle(m.phi())}, static_cast<int>(info.nIterations)};
}

// Both registrations of `moving` onto `fixed` from `start`: the poses agree
// within 2 mm and 0.2 mrad, and ours is within `truth_xy` of `truth`.
void expect_same_as_mrpt(const grid::OccupancyGrid& moving, const grid::OccupancyGrid& fixed,
                         const Pose2D& start, const Pose2D& truth, double truth_xy) {
  const AlignmentOptions opt;
  const std::vector<Point2D> m = occupied_points(moving, opt);
  const std::vector<Point2D> f = occupied_points(fixed, opt);
  ASSERT_GT(m.size(), 200u);
  ASSERT_GT(f.size(), 200u);
  const IcpResult ours = icp_register(m, f, start, opt);
  const MrptResult theirs = mrpt_icp(m, f, start, opt);
  const double dxy = std::hypot(ours.pose.x - theirs.pose.x, ours.pose.y - theirs.pose.y);
  const double dth = std::abs(wrap_angle(ours.pose.theta - theirs.pose.theta));
  std::printf("  %zu/%zu points: ours (%.5f, %.5f, %.6f) in %d, MRPT (%.5f, %.5f, %.6f) "
              "in %d; difference %.2e m, %.2e rad\n",
              m.size(), f.size(), ours.pose.x, ours.pose.y, ours.pose.theta, ours.iterations,
              theirs.pose.x, theirs.pose.y, theirs.pose.theta, theirs.iterations, dxy, dth);
  EXPECT_LT(dxy, 2e-3);
  EXPECT_LT(dth, 2e-4);
  EXPECT_LT(std::hypot(ours.pose.x - truth.x, ours.pose.y - truth.y), truth_xy);
}

TEST(IcpVsMrpt, TheRoomsOfTheAlignmentTests) {
  const Pose2D truth(0.3, -0.2, 0.1);
  const grid::OccupancyGrid fixed = scanned_grid(room_world(), room_tour_a(), Pose2D(), 1);
  const grid::OccupancyGrid moving = scanned_grid(room_world(), room_tour_b(), truth, 2);
  const double dirs[4] = {0.0, 2.0, 3.5, 5.0};
  for (int k = 0; k < 4; ++k) {
    SCOPED_TRACE(k);
    const double sign = (k % 2) ? -1.0 : 1.0;
    const Pose2D guess(truth.x + 0.15 * std::cos(dirs[k]), truth.y + 0.15 * std::sin(dirs[k]),
                       truth.theta + sign * 0.05);
    expect_same_as_mrpt(moving, fixed, guess, truth, 0.02);
  }
  {
    SCOPED_TRACE("inverse");
    expect_same_as_mrpt(fixed, moving, truth.inverse() + Pose2D(-0.1, 0.11, -0.05),
                        truth.inverse(), 0.02);
  }
  {
    SCOPED_TRACE("overlapping halves");
    const grid::OccupancyGrid west =
        crop(moving, truth, [](const Point2D& p) { return p.x < 13.0; });
    const grid::OccupancyGrid east =
        crop(fixed, Pose2D(), [](const Point2D& p) { return p.x > 6.0; });
    expect_same_as_mrpt(west, east, truth + Pose2D(-0.1, 0.11, -0.05), truth, 0.02);
  }
}

// Grids of the Edmonton log (CARMEN, in the repository) at the reference
// poses: scans [first, last) inserted in the frame of scan `frame`.
class Edmonton : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    const std::string dir = std::string(HMT_SOURCE_DIR) + "/datasets/";
    log_ = new Log(io::read_log(dir + "edmonton.log.gz"));
    const auto ref = grouping::read_pose_file(dir + "edmonton.reference.txt.gz");
    poses_ = new grouping::ScanPoses(grouping::match_poses(*log_, ref, 0.01, "reference"));
  }
  static void TearDownTestSuite() {
    delete log_;
    delete poses_;
  }
  static grid::OccupancyGrid grid_of(size_t first, size_t last, size_t frame) {
    grid::OccupancyGrid g(0.05);
    const Pose2D origin = poses_->pose[frame];
    for (size_t i = first; i < last; ++i)
      if (poses_->has_pose[i])
        grid::insert_scan(g, poses_->pose[i] - origin, log_->steps[i].scan,
                          grid::InsertionOptions{});
    return g;
  }
  static Pose2D pose(size_t i) { return poses_->pose[i]; }

  static Log* log_;
  static grouping::ScanPoses* poses_;
};
Log* Edmonton::log_ = nullptr;
grouping::ScanPoses* Edmonton::poses_ = nullptr;

// The reference is a GMapping run, good to a few centimetres: the truth
// bound is loose; the comparison with MRPT is not.
void expect_same_as_mrpt_from(const grid::OccupancyGrid& moving,
                              const grid::OccupancyGrid& fixed, const Pose2D& truth,
                              double truth_xy = 0.05) {
  for (const Pose2D& off : {Pose2D(0.15, -0.1, 0.04), Pose2D(-0.1, -0.12, -0.03)}) {
    SCOPED_TRACE(off.x);
    expect_same_as_mrpt(moving, fixed, truth + off, truth, truth_xy);
  }
}

TEST_F(Edmonton, ARevisitedHall) {
  // The robot passes the same hall at scans 165-195 and again at 225-255.
  expect_same_as_mrpt_from(grid_of(220, 260, 220), grid_of(160, 200, 160),
                           pose(220) - pose(160));
}

TEST_F(Edmonton, TheStartRevisited) {
  // Little overlap (a quarter of the moving points pair at the end; the
  // alignment rejects it): both ICPs run to the iteration limit and end at
  // the same pose, 13 cm from the reference.
  expect_same_as_mrpt_from(grid_of(50, 75, 55), grid_of(0, 20, 0), pose(55) - pose(0), 0.2);
}

TEST_F(Edmonton, ConsecutiveStretches) {
  expect_same_as_mrpt_from(grid_of(120, 150, 130), grid_of(100, 130, 100),
                           pose(130) - pose(100));
}

}  // namespace
}  // namespace hmt::alignment
