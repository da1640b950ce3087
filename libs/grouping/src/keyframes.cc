#include "hmt/grouping/keyframes.h"

#include <cmath>

#include "hmt/area/scan_sso.h"

namespace hmt::grouping {
KeyframeSelection select_keyframes(const Log& log, const ScanPoses& poses,
                                   double distance, double angle) {
  KeyframeSelection out;
  bool have_last = false;
  Pose2D last;
  for (size_t i = 0; i < poses.size(); ++i) {
    if (!poses.has_pose[i]) continue;
    const Pose2D& p = poses.pose[i];
    if (have_last) {
      const double moved = std::hypot(p.x - last.x, p.y - last.y);
      const double turned = std::fabs(wrap_angle(p.theta - last.theta));
      if (moved < distance && turned < angle) continue;
    }
    if (!area::enough_returns(log.steps[i].scan)) {
      ++out.too_few_returns;
      continue;
    }
    out.keyframes.push_back({static_cast<int>(i), log.steps[i].timestamp, p});
    last = p;
    have_last = true;
  }
  return out;
}

std::vector<area::Keyframe> area_keyframes(
    const Log& log, const std::vector<KeyframeRecord>& keyframes) {
  std::vector<area::Keyframe> out;
  out.reserve(keyframes.size());
  for (const KeyframeRecord& k : keyframes) {
    area::Keyframe kf;
    kf.pose = area::PoseGaussian(k.pose);
    kf.scan = log.steps[static_cast<size_t>(k.scan)].scan;
    out.push_back(std::move(kf));
  }
  return out;
}

}  // namespace hmt::grouping
