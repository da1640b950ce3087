#include "hmt/grouping/grouping_options.h"

#include <cmath>

#include "hmt/common/config.h"

namespace hmt::grouping {

void GroupingOptions::load(Config& cfg, const std::string& s) {
  keyframe_distance = cfg.get_double(s, "keyframe_distance", keyframe_distance);
  keyframe_angle = cfg.get_double(s, "keyframe_angle", keyframe_angle);
  pose_time_tolerance =
      cfg.get_double(s, "pose_time_tolerance", pose_time_tolerance);
  refine_local_maps = cfg.get_bool(s, "refine_local_maps", refine_local_maps);
  validate(s);
}

void GroupingOptions::validate(const std::string& s) const {
  require(std::isfinite(keyframe_distance) && keyframe_distance >= 0.0, s,
          "keyframe_distance", ">= 0 (metres)");
  require(std::isfinite(keyframe_angle) && keyframe_angle >= 0.0, s,
          "keyframe_angle", ">= 0 (radians)");
  require(std::isfinite(pose_time_tolerance) && pose_time_tolerance >= 0.0, s,
          "pose_time_tolerance", ">= 0 (seconds)");
}

}  // namespace hmt::grouping
