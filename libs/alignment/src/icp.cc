#include "hmt/alignment/icp.h"

#include <nanoflann.hpp>

#include <cmath>
#include <cstdint>

namespace hmt::alignment {
namespace {

// Why a k-d tree rather than the fixed grid's cells (as FixedIndex in
// grid_alignment.cc): the pairing radius starts at a metre or more plus the
// angular term (2-3 m for points 20-30 m away), a window of up to 100 x 100
// cells of 5 cm per query, and ICP wants the nearest point whatever the
// radius. The tree answers in O(log n), exactly; nanoflann is header-only
// and is the tree MRPT's CICP pairs with, so the pairs are the same.
struct PointCloud {
  const std::vector<Point2D>& pts;
  size_t kdtree_get_point_count() const { return pts.size(); }
  double kdtree_get_pt(size_t i, size_t dim) const {
    return dim == 0 ? pts[i].x : pts[i].y;
  }
  template <class Box>
  bool kdtree_get_bbox(Box&) const {
    return false;  // let the tree compute it
  }
};
using KdTree = nanoflann::KDTreeSingleIndexAdaptor<
    nanoflann::L2_Simple_Adaptor<double, PointCloud>, PointCloud, 2, uint32_t>;

struct Pair {
  Point2D moving;  // in moving's frame
  Point2D fixed;
};

// The least-squares rigid transform T with fixed ~ T(moving) over the pairs
// (at least 2): centred sums, so that coordinates far from the origin lose
// no precision.
Pose2D fit_rigid(const std::vector<Pair>& pairs) {
  const double n = static_cast<double>(pairs.size());
  double mx = 0, my = 0, fx = 0, fy = 0;
  for (const Pair& p : pairs) {
    mx += p.moving.x, my += p.moving.y;
    fx += p.fixed.x, fy += p.fixed.y;
  }
  mx /= n, my /= n, fx /= n, fy /= n;
  double dot = 0, cross = 0;  // sum of m' . f' and m' x f'
  for (const Pair& p : pairs) {
    const double ax = p.moving.x - mx, ay = p.moving.y - my;
    const double bx = p.fixed.x - fx, by = p.fixed.y - fy;
    dot += ax * bx + ay * by;
    cross += ax * by - ay * bx;
  }
  const double theta = (dot != 0.0 || cross != 0.0) ? std::atan2(cross, dot) : 0.0;
  const double c = std::cos(theta), s = std::sin(theta);
  return {fx - (c * mx - s * my), fy - (s * mx + c * my), theta};
}

}  // namespace

IcpResult icp_register(const std::vector<Point2D>& moving,
                       const std::vector<Point2D>& fixed, const Pose2D& start,
                       const AlignmentOptions& opt) {
  IcpResult res;
  res.pose = start;
  if (moving.empty() || fixed.empty()) return res;

  const PointCloud cloud{fixed};
  const KdTree tree(2, cloud, nanoflann::KDTreeSingleIndexAdaptorParams(10));

  constexpr double kMinStep = 1e-6;  // [m] and [rad]: "the pose settled"
  double threshold = opt.icp_threshold_start;
  double angular = opt.icp_threshold_angular;
  std::vector<Pair> pairs;
  pairs.reserve(moving.size());
  for (;;) {
    const Pose2D pose = res.pose;
    pairs.clear();
    for (const Point2D& p : moving) {
      const Point2D x = pose.transform(p);
      const double query[2] = {x.x, x.y};
      uint32_t index = 0;
      double d2 = 0.0;
      if (tree.knnSearch(query, 1, &index, &d2) != 1) continue;
      const double reach =
          angular * std::hypot(x.x - pose.x, x.y - pose.y) + threshold;
      if (d2 < reach * reach) pairs.push_back({p, fixed[index]});
    }
    res.pairs = static_cast<int>(pairs.size());
    bool keep_going = false;
    if (pairs.size() >= 2) {
      res.pose = fit_rigid(pairs);
      keep_going = true;
      if (std::abs(res.pose.x - pose.x) <= kMinStep &&
          std::abs(res.pose.y - pose.y) <= kMinStep &&
          std::abs(wrap_angle(res.pose.theta - pose.theta)) <= kMinStep) {
        threshold *= opt.icp_threshold_decay;
        angular *= opt.icp_threshold_decay;
        keep_going = threshold >= opt.icp_threshold_end;
      }
    }
    ++res.iterations;
    if (res.iterations < opt.icp_max_iterations) {
      if (!keep_going) break;
    } else {
      // Out of budget: finish at the fine threshold, decaying every round.
      if (threshold > opt.icp_threshold_end) threshold *= opt.icp_threshold_decay;
      if (!(threshold > opt.icp_threshold_end)) break;
    }
  }
  res.pose.theta = wrap_angle(res.pose.theta);
  return res;
}

}  // namespace hmt::alignment
