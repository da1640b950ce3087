#include "hmt/alignment/grid_alignment.h"

namespace hmt::alignment {

void AlignmentOptions::load(Config& cfg, const std::string& s) {
  occupied_probability = cfg.get_double(s, "occupied_probability", occupied_probability);
  min_hits = cfg.get_int(s, "min_hits", min_hits);
  min_points = cfg.get_int(s, "min_points", min_points);
  icp_threshold_start = cfg.get_double(s, "icp_threshold_start", icp_threshold_start);
  icp_threshold_angular = cfg.get_double(s, "icp_threshold_angular", icp_threshold_angular);
  icp_threshold_decay = cfg.get_double(s, "icp_threshold_decay", icp_threshold_decay);
  icp_threshold_end = cfg.get_double(s, "icp_threshold_end", icp_threshold_end);
  icp_max_iterations = cfg.get_int(s, "icp_max_iterations", icp_max_iterations);
  refine_iterations = cfg.get_int(s, "refine_iterations", refine_iterations);
  match_distance = cfg.get_double(s, "match_distance", match_distance);
  normal_radius = cfg.get_double(s, "normal_radius", normal_radius);
  robust_scale = cfg.get_double(s, "robust_scale", robust_scale);
  covariance_inflation = cfg.get_double(s, "covariance_inflation", covariance_inflation);
  sigma_floor_xy = cfg.get_double(s, "sigma_floor_xy", sigma_floor_xy);
  sigma_floor_theta = cfg.get_double(s, "sigma_floor_theta", sigma_floor_theta);
  min_inlier_ratio = cfg.get_double(s, "min_inlier_ratio", min_inlier_ratio);
  gate_chi2 = cfg.get_double(s, "gate_chi2", gate_chi2);
  min_information_ratio = cfg.get_double(s, "min_information_ratio", min_information_ratio);
  max_sigma_xy = cfg.get_double(s, "max_sigma_xy", max_sigma_xy);
  max_sigma_theta = cfg.get_double(s, "max_sigma_theta", max_sigma_theta);

  // Every test is written so that NaN fails it.
  require(occupied_probability > 0.5 && occupied_probability < 0.97, s,
          "occupied_probability", "in (0.5, 0.97)");
  require(min_hits >= 1 && min_hits <= 255, s, "min_hits", "in [1, 255]");
  require(min_points >= 3, s, "min_points", ">= 3");
  require(icp_threshold_start > 0 && icp_threshold_start <= 10, s,
          "icp_threshold_start", "in (0, 10] metres");
  require(icp_threshold_angular >= 0 && icp_threshold_angular <= 1, s,
          "icp_threshold_angular", "in [0, 1] radians");
  require(icp_threshold_decay > 0 && icp_threshold_decay < 1, s,
          "icp_threshold_decay", "in (0, 1)");
  require(icp_threshold_end > 0 && icp_threshold_end <= icp_threshold_start, s,
          "icp_threshold_end", "in (0, icp_threshold_start]");
  require(icp_max_iterations >= 1 && icp_max_iterations <= 10000, s,
          "icp_max_iterations", "in [1, 10000]");
  require(refine_iterations >= 0 && refine_iterations <= 100, s,
          "refine_iterations", "in [0, 100]");
  require(match_distance > 0 && match_distance <= 2, s, "match_distance",
          "in (0, 2] metres");
  require(normal_radius > 0 && normal_radius <= 2, s, "normal_radius",
          "in (0, 2] metres");
  require(robust_scale > 0, s, "robust_scale", "> 0");
  require(covariance_inflation >= 1 && covariance_inflation <= 1000, s,
          "covariance_inflation", "in [1, 1000]");
  require(sigma_floor_xy > 0 && sigma_floor_xy < 1, s, "sigma_floor_xy",
          "in (0, 1) metres");
  require(sigma_floor_theta > 0 && sigma_floor_theta < 1, s,
          "sigma_floor_theta", "in (0, 1) radians");
  require(min_inlier_ratio >= 0 && min_inlier_ratio <= 1, s,
          "min_inlier_ratio", "in [0, 1]");
  require(gate_chi2 > 0 && gate_chi2 < 1e6, s, "gate_chi2", "in (0, 1e6)");
  require(min_information_ratio >= 0 && min_information_ratio < 1, s,
          "min_information_ratio", "in [0, 1)");
  require(max_sigma_xy > sigma_floor_xy && max_sigma_xy < 1e3, s,
          "max_sigma_xy", "> sigma_floor_xy and < 1000");
  require(max_sigma_theta > sigma_floor_theta && max_sigma_theta < 1e3, s,
          "max_sigma_theta", "> sigma_floor_theta and < 1000");
}

}  // namespace hmt::alignment
