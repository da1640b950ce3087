#include "bag_frames.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <set>

#include "hmt/common/error.h"

namespace hmt::io::detail {

std::string frame_name(const std::string& frame) {
  return !frame.empty() && frame[0] == '/' ? frame.substr(1) : frame;
}

Rigid to_rigid(const BagTransform& t, const std::string& what) {
  const Eigen::Quaterniond& q = t.rotation;
  const double norm = q.norm();
  if (!t.translation.allFinite() || !q.coeffs().allFinite() || !(norm > 1e-6))
    throw InputError(what + " is not a rigid transform (translation " +
                     std::to_string(t.translation.x()) + " " +
                     std::to_string(t.translation.y()) + " " +
                     std::to_string(t.translation.z()) + ", quaternion of norm " +
                     std::to_string(norm) + ")");
  return {std::abs(norm - 1.0) > 1e-9 ? q.normalized() : q, t.translation};
}

Pose2D planar(const Rigid& pose) {
  const Eigen::Quaterniond& q = pose.rotation;
  const double yaw = std::atan2(2.0 * (q.w() * q.z() + q.x() * q.y()),
                                q.w() * q.w() + q.x() * q.x() - q.y() * q.y() - q.z() * q.z());
  return Pose2D(pose.translation.x(), pose.translation.y(), yaw);
}

void TransformSeries::add(double stamp, const Rigid& pose) {
  samples_.emplace_back(stamp, pose);
}

void TransformSeries::finish() {
  std::stable_sort(samples_.begin(), samples_.end(),
                   [](const auto& a, const auto& b) { return a.first < b.first; });
}

std::optional<Rigid> TransformSeries::at(double t) const {
  const auto it = std::lower_bound(
      samples_.begin(), samples_.end(), t,
      [](const auto& s, double v) { return s.first < v; });
  if (it != samples_.end() && it->first == t) return it->second;
  if (it == samples_.begin() || it == samples_.end()) return std::nullopt;
  const auto& [t0, p0] = *std::prev(it);
  const auto& [t1, p1] = *it;
  const double a = (t - t0) / (t1 - t0);
  return Rigid{p0.rotation.slerp(a, p1.rotation),
               (1.0 - a) * p0.translation + a * p1.translation};
}

FrameTree::FrameTree(const std::vector<BagTransform>& dynamic,
                     const std::vector<BagTransform>& fixed,
                     const std::string& source) {
  auto add = [&](const BagTransform& t, bool is_static) {
    const std::string parent = frame_name(t.parent), child = frame_name(t.child);
    const char* topic = is_static ? kTfStaticTopic : kTfTopic;
    const std::string what = "ROS bag '" + source + "': the transform '" + parent +
                             "' -> '" + child + "' on " + topic;
    if (parent.empty() || child.empty() || parent == child)
      throw InputError(what + " does not name two frames");
    const Rigid pose = to_rigid(t, what);
    auto [it, fresh] = links_.try_emplace(child);
    Link& link = it->second;
    if (fresh) {
      link.parent = parent;
      link.is_static = is_static;
    } else if (link.parent != parent) {
      throw InputError("ROS bag '" + source + "': frame '" + child +
                       "' has two parents, '" + link.parent + "' and '" + parent +
                       "' (a tf tree gives each frame one)");
    } else if (link.is_static != is_static) {
      throw InputError("ROS bag '" + source + "': the transform '" + parent +
                       "' -> '" + child + "' is both on /tf and on /tf_static");
    }
    if (is_static)
      link.fixed = pose;  // a later /tf_static message replaces an earlier one
    else
      link.series.add(t.stamp, pose);
  };
  for (const BagTransform& t : fixed) add(t, true);
  for (const BagTransform& t : dynamic) add(t, false);
  for (auto& [child, link] : links_)
    if (!link.is_static) link.series.finish();
}

std::vector<std::string> FrameTree::ancestors(const std::string& frame) const {
  std::vector<std::string> out{frame};
  for (auto it = links_.find(frame); it != links_.end();
       it = links_.find(it->second.parent)) {
    // A chain longer than the links is a cycle (A parent of B parent of A).
    if (out.size() > links_.size()) break;
    out.push_back(it->second.parent);
  }
  return out;
}

std::optional<Rigid> FrameTree::lookup(const std::string& parent,
                                                   const std::string& child,
                                                   double t, std::string& why) const {
  const std::vector<std::string> up_child = ancestors(child);
  const std::vector<std::string> up_parent = ancestors(parent);
  // The first common ancestor, and how far up each chain it is.
  std::optional<std::pair<size_t, size_t>> common;
  for (size_t a = 0; a < up_child.size() && !common; ++a) {
    const auto it = std::find(up_parent.begin(), up_parent.end(), up_child[a]);
    if (it != up_parent.end())
      common = std::make_pair(a, static_cast<size_t>(it - up_parent.begin()));
  }
  if (!common) {
    why = "no chain of transforms connects '" + parent + "' and '" + child + "'";
    return std::nullopt;
  }
  auto in_ancestor = [&](const std::vector<std::string>& chain,
                         size_t n) -> std::optional<Rigid> {
    Rigid pose;
    for (size_t k = 0; k < n; ++k) {
      const Link& link = links_.at(chain[k]);
      if (link.is_static) {
        pose = link.fixed * pose;
        continue;
      }
      const auto p = link.series.at(t);
      if (!p) {
        char span[96];
        std::snprintf(span, sizeof span, "%.6f s, outside its samples' span [%.6f, %.6f] s",
                      t, link.series.first_stamp(), link.series.last_stamp());
        why = "the transform '" + link.parent + "' -> '" + chain[k] + "' has no sample around " +
              span;
        return std::nullopt;
      }
      pose = *p * pose;
    }
    return pose;
  };
  const auto child_pose = in_ancestor(up_child, common->first);
  if (!child_pose) return std::nullopt;
  const auto parent_pose = in_ancestor(up_parent, common->second);
  if (!parent_pose) return std::nullopt;
  return parent_pose->inverse() * *child_pose;
}

bool FrameTree::connected(const std::string& a, const std::string& b) const {
  if (a == b) return true;
  const std::vector<std::string> up_a = ancestors(a), up_b = ancestors(b);
  // Frames of one tree share its root (a frame no transform names is its
  // own root).
  return up_a.back() == up_b.back();
}

std::vector<std::string> FrameTree::frames() const {
  std::set<std::string> names;
  for (const auto& [child, link] : links_) {
    names.insert(child);
    names.insert(link.parent);
  }
  return {names.begin(), names.end()};
}

}  // namespace hmt::io::detail
