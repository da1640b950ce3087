#include "hmt/area/pose_gaussian.h"

#include <cmath>

namespace hmt::area {

PoseGaussian relative_pose(const PoseGaussian& of, const PoseGaussian& from) {
  // q = from^-1 (+) of. With c, s of from.theta and d = of.t - from.t:
  //   q.x =  c dx + s dy,  q.y = -s dx + c dy,  q.theta = of.theta - from.theta
  PoseGaussian q;
  q.mean = of.mean - from.mean;
  const double c = std::cos(from.mean.theta), s = std::sin(from.mean.theta);
  Eigen::Matrix3d J_of;
  J_of << c, s, 0, -s, c, 0, 0, 0, 1;
  Eigen::Matrix3d J_from;
  J_from << -c, -s, q.mean.y, s, -c, -q.mean.x, 0, 0, -1;
  q.cov =
      J_of * of.cov * J_of.transpose() + J_from * from.cov * J_from.transpose();
  return q;
}

Eigen::Matrix2d compose_point_cov(const PoseGaussian& q, const Point2D& p,
                                  const Eigen::Matrix2d& cov_p) {
  return PointComposer(q).cov(p, cov_p);
}

Eigen::Matrix2d range_bearing_cov(double r, double phi, double range_std,
                                  double bearing_std) {
  const double c = std::cos(phi), s = std::sin(phi);
  Eigen::Matrix2d J;
  J << c, -r * s, s, r * c;
  const Eigen::Vector2d var(range_std * range_std, bearing_std * bearing_std);
  return J * var.asDiagonal() * J.transpose();
}

}  // namespace hmt::area
