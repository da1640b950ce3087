#include "hmt/metric_slam/motion_model.h"

#include <cmath>

namespace hmt::metric_slam {

void MotionOptions::load(Config& cfg, const std::string& s) {
  srr = cfg.get_double(s, "srr", srr);
  srt = cfg.get_double(s, "srt", srt);
  str = cfg.get_double(s, "str", str);
  stt = cfg.get_double(s, "stt", stt);
  min_sigma_xy = cfg.get_double(s, "min_sigma_xy", min_sigma_xy);
  min_sigma_theta = cfg.get_double(s, "min_sigma_theta", min_sigma_theta);
  require(srr >= 0, s, "srr", ">= 0");
  require(srt >= 0, s, "srt", ">= 0");
  require(str >= 0, s, "str", ">= 0");
  require(stt >= 0, s, "stt", ">= 0");
  require(min_sigma_xy > 0, s, "min_sigma_xy", "> 0");
  require(min_sigma_theta > 0, s, "min_sigma_theta", "> 0");
}

MotionSigmas MotionModel::sigmas(const Pose2D& u) const {
  const double d = std::hypot(u.x, u.y), a = std::fabs(u.theta);
  return {opt_.min_sigma_xy + opt_.srr * d + opt_.srt * a,
          opt_.min_sigma_theta + opt_.stt * a + opt_.str * d};
}

double MotionModel::distance_sigma(const Pose2D& u) const {
  return opt_.min_sigma_xy + opt_.srr * std::hypot(u.x, u.y);
}

Pose2D MotionModel::sample(const Pose2D& prev, const Pose2D& u, Random& rng) const {
  const MotionSigmas s = sigmas(u);
  const Pose2D noisy(u.x + rng.normal(0, s.xy), u.y + rng.normal(0, s.xy),
                     u.theta + rng.normal(0, s.theta));
  return prev + noisy;
}

double MotionModel::log_density(const Pose2D& prev, const Pose2D& u,
                                const Pose2D& x) const {
  const MotionSigmas s = sigmas(u);
  const Pose2D v = x - prev;
  const double ex = v.x - u.x, ey = v.y - u.y, et = wrap_angle(v.theta - u.theta);
  return -0.5 * ((ex * ex + ey * ey) / (s.xy * s.xy) + et * et / (s.theta * s.theta));
}

}  // namespace hmt::metric_slam
