// A rigid 2D transform / robot pose (x, y, heading), with the usual
// composition operators of the SLAM literature:
//   a + b  : a (+) b, b expressed in the frame a, composed into a's parent frame
//   a - b  : a (-) b, the pose a seen from the frame b  (== b.inverse() + a)
// Kept header-only and free of MRPT so that the hot loops stay inlinable.
#pragma once

#include <cmath>

namespace hmt {

inline double wrap_angle(double a) {
  // Into (-pi, pi]. remainder() is exact and has no drift for big inputs.
  double r = std::remainder(a, 2.0 * M_PI);
  if (r <= -M_PI) r += 2.0 * M_PI;
  return r;
}

struct Point2D {
  double x = 0.0;
  double y = 0.0;
};

struct Pose2D {
  double x = 0.0;
  double y = 0.0;
  double theta = 0.0;

  Pose2D() = default;
  Pose2D(double x_, double y_, double theta_) : x(x_), y(y_), theta(theta_) {}

  Pose2D operator+(const Pose2D& b) const {
    const double c = std::cos(theta), s = std::sin(theta);
    return {x + c * b.x - s * b.y, y + s * b.x + c * b.y,
            wrap_angle(theta + b.theta)};
  }
  Pose2D inverse() const {
    const double c = std::cos(theta), s = std::sin(theta);
    return {-c * x - s * y, s * x - c * y, wrap_angle(-theta)};
  }
  Pose2D operator-(const Pose2D& b) const { return b.inverse() + *this; }

  Point2D transform(const Point2D& p) const {
    const double c = std::cos(theta), s = std::sin(theta);
    return {x + c * p.x - s * p.y, y + s * p.x + c * p.y};
  }
  double norm() const { return std::hypot(x, y); }
};

// Whether a motion `moved` (e.g. b - a) stays under both thresholds of a
// spacing (keyframes, map updates, filter updates, merged modes): less
// than `distance` metres and `angle` radians.
inline bool within_spacing(const Pose2D& moved, double distance, double angle) {
  return moved.norm() < distance && std::fabs(moved.theta) < angle;
}

}  // namespace hmt
