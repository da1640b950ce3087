// The transforms of a ROS bag as tf keeps them: a tree of frames, each
// frame's pose in its parent either static (/tf_static) or a time series
// (/tf, or an Odometry topic), looked up at a time by interpolating every
// link of the chain between two frames. Only what the bag reader needs:
// no caching, no time travel between two stamps.
#pragma once

#include <Eigen/Geometry>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "bag_contents.h"
#include "hmt/common/pose2d.h"

namespace hmt::io::detail {

// A rigid transform as tf keeps it: rotation quaternion and translation.
// Quaternions are used as the bag gives them when their norm is 1 to
// rounding (planar() reads the heading without normalising, so a written
// yaw is read back bit for bit), normalised otherwise.
struct Rigid {
  Eigen::Quaterniond rotation = Eigen::Quaterniond::Identity();
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();

  Rigid operator*(const Rigid& b) const {
    return {rotation * b.rotation, translation + rotation * b.translation};
  }
  Rigid inverse() const {
    const Eigen::Quaterniond q = rotation.conjugate();
    return {q, -(q * translation)};
  }
  // The laser's z axis in its parent frame, z component: 1 level, -1
  // upside down.
  double up() const {
    const Eigen::Quaterniond& q = rotation;
    return 1.0 - 2.0 * (q.x() * q.x() + q.y() * q.y());
  }
};

// tf2 drops a leading '/' from frame names (tf1 wrote "/base_link").
std::string frame_name(const std::string& frame);

// A time series of one frame's pose in another. Samples at the same stamp
// keep their order; at() takes the first of them.
class TransformSeries {
 public:
  void add(double stamp, const Rigid& pose);
  // Sorts the samples by stamp; call once after the last add().
  void finish();
  bool empty() const { return samples_.empty(); }
  double first_stamp() const { return samples_.front().first; }
  double last_stamp() const { return samples_.back().first; }
  // The pose at `t`: the sample at t itself, else interpolated between the
  // samples around t (translation linearly, rotation by slerp); nullopt
  // outside [first_stamp, last_stamp].
  std::optional<Rigid> at(double t) const;

 private:
  std::vector<std::pair<double, Rigid>> samples_;
};

class FrameTree {
 public:
  // Throws hmt::InputError (naming `source`, the bag) for a frame with two
  // parents, a frame both static and dynamic, an invalid rotation.
  FrameTree(const std::vector<BagTransform>& dynamic,
            const std::vector<BagTransform>& fixed, const std::string& source);

  // The pose of `child` in `parent` at time t, composed along the tree;
  // nullopt with `why` saying what is missing (the frames are not
  // connected, or a link has no sample around t).
  std::optional<Rigid> lookup(const std::string& parent,
                                          const std::string& child, double t,
                                          std::string& why) const;

  // Whether a chain of transforms joins the two frames (at some time).
  bool connected(const std::string& a, const std::string& b) const;

  // The frames that appear, sorted (for messages).
  std::vector<std::string> frames() const;
  bool empty() const { return links_.empty(); }

 private:
  struct Link {
    std::string parent;
    bool is_static = false;
    Rigid fixed;
    TransformSeries series;
  };
  // `frame` and its ancestors, up to the root.
  std::vector<std::string> ancestors(const std::string& frame) const;
  std::map<std::string, Link> links_;  // by child frame
};

// A transform's rotation and translation as a rigid transform; throws
// hmt::InputError (saying `what`) for a non-finite value or a zero
// quaternion.
Rigid to_rigid(const BagTransform& t, const std::string& what);

// The planar part: x, y and the heading of the x axis seen from above,
// atan2(2(wz + xy), w^2 + x^2 - y^2 - z^2) as tf2::getYaw() has it.
Pose2D planar(const Rigid& pose);

}  // namespace hmt::io::detail
