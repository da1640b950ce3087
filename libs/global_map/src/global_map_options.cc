#include "hmt/global_map/global_map_options.h"

#include <cmath>

namespace hmt::global_map {
namespace {

void require_std(double v, const std::string& s, const char* key) {
  require(std::isfinite(v) && v >= 0.0, s, key, ">= 0 and finite");
}

}  // namespace

void KeyframeGraphOptions::load(Config& cfg, const std::string& s) {
  in_area_std_xy = cfg.get_double(s, "in_area_std_xy", in_area_std_xy);
  in_area_std_xy_per_metre = cfg.get_double(s, "in_area_std_xy_per_metre", in_area_std_xy_per_metre);
  in_area_std_theta = cfg.get_double(s, "in_area_std_theta", in_area_std_theta);
  in_area_std_theta_per_metre =
      cfg.get_double(s, "in_area_std_theta_per_metre", in_area_std_theta_per_metre);
  step_std_xy = cfg.get_double(s, "step_std_xy", step_std_xy);
  step_std_xy_per_metre = cfg.get_double(s, "step_std_xy_per_metre", step_std_xy_per_metre);
  step_std_theta = cfg.get_double(s, "step_std_theta", step_std_theta);
  step_std_theta_per_metre = cfg.get_double(s, "step_std_theta_per_metre", step_std_theta_per_metre);
  step_std_theta_per_radian =
      cfg.get_double(s, "step_std_theta_per_radian", step_std_theta_per_radian);
  match = cfg.get_bool(s, "match", match);
  match_own_area = cfg.get_bool(s, "match_own_area", match_own_area);
  match_min_ratio = cfg.get_double(s, "match_min_ratio", match_min_ratio);
  match_gate_xy = cfg.get_double(s, "match_gate_xy", match_gate_xy);
  match_gate_theta = cfg.get_double(s, "match_gate_theta", match_gate_theta);
  match_inflation = cfg.get_double(s, "match_inflation", match_inflation);
  match_std_xy = cfg.get_double(s, "match_std_xy", match_std_xy);
  match_std_theta = cfg.get_double(s, "match_std_theta", match_std_theta);
  match_reuse = cfg.get_bool(s, "match_reuse", match_reuse);
  const std::string k = cfg.get_string(s, "robust_kernel", kernel == RobustKernel::kDcs ? "dcs" : "huber");
  require(k == "dcs" || k == "huber", s, "robust_kernel", "dcs or huber");
  kernel = k == "dcs" ? RobustKernel::kDcs : RobustKernel::kHuber;
  robust_chi2 = cfg.get_double(s, "robust_chi2", robust_chi2);
  rounds = cfg.get_int(s, "rounds", rounds);
  round_tolerance = cfg.get_double(s, "round_tolerance", round_tolerance);
  max_iterations = cfg.get_int(s, "max_iterations", max_iterations);
  relative_tolerance = cfg.get_double(s, "relative_tolerance", relative_tolerance);

  // The constant parts are the floors of each covariance: zero would make a
  // constraint over no motion infinitely certain.
  require(std::isfinite(in_area_std_xy) && in_area_std_xy > 0, s, "in_area_std_xy", "> 0");
  require(std::isfinite(in_area_std_theta) && in_area_std_theta > 0, s, "in_area_std_theta", "> 0");
  require(std::isfinite(step_std_xy) && step_std_xy > 0, s, "step_std_xy", "> 0");
  require(std::isfinite(step_std_theta) && step_std_theta > 0, s, "step_std_theta", "> 0");
  require(std::isfinite(match_std_xy) && match_std_xy > 0, s, "match_std_xy", "> 0");
  require(std::isfinite(match_std_theta) && match_std_theta > 0, s, "match_std_theta", "> 0");
  require_std(in_area_std_xy_per_metre, s, "in_area_std_xy_per_metre");
  require_std(in_area_std_theta_per_metre, s, "in_area_std_theta_per_metre");
  require_std(step_std_xy_per_metre, s, "step_std_xy_per_metre");
  require_std(step_std_theta_per_metre, s, "step_std_theta_per_metre");
  require_std(step_std_theta_per_radian, s, "step_std_theta_per_radian");
  require(match_min_ratio > 0 && match_min_ratio <= 1, s, "match_min_ratio", "in (0, 1]");
  require(std::isfinite(match_gate_xy) && match_gate_xy > 0, s, "match_gate_xy", "> 0");
  require(std::isfinite(match_gate_theta) && match_gate_theta > 0, s, "match_gate_theta", "> 0");
  require(std::isfinite(match_inflation) && match_inflation >= 1, s, "match_inflation", ">= 1");
  require(std::isfinite(robust_chi2) && robust_chi2 > 0, s, "robust_chi2", "> 0");
  require(rounds >= 1 && rounds <= 100, s, "rounds", "in [1, 100]");
  require(std::isfinite(round_tolerance) && round_tolerance >= 0, s, "round_tolerance", ">= 0");
  require(max_iterations >= 1, s, "max_iterations", ">= 1");
  require(relative_tolerance > 0 && relative_tolerance < 1, s, "relative_tolerance", "in (0, 1)");
}

void GlobalMapOptions::load(Config& cfg, const std::string& s) {
  const std::string m =
      cfg.get_string(s, "method", method == GlobalMapMethod::kKeyframes ? "keyframes" : "areas");
  require(m == "keyframes" || m == "areas", s, "method", "keyframes or areas");
  method = m == "keyframes" ? GlobalMapMethod::kKeyframes : GlobalMapMethod::kAreas;
  graph.load(cfg, s);
}

}  // namespace hmt::global_map
