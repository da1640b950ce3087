#include "hmt/tsbi/tsbi_options.h"

#include <cmath>

namespace hmt::tsbi {

void TsbiOptions::load(Config& cfg, const std::string& s) {
  log_eta = cfg.get_double(s, "log_eta", log_eta);
  min_match_ratio = cfg.get_double(s, "min_match_ratio", min_match_ratio);
  min_points_explained = cfg.get_double(s, "min_points_explained", min_points_explained);
  max_points_contradicted = cfg.get_double(s, "max_points_contradicted", max_points_contradicted);
  free_probability = cfg.get_double(s, "free_probability", free_probability);
  gate = cfg.get_double(s, "gate", gate);
  max_points = cfg.get_int(s, "max_points", max_points);
  evidence_cell = cfg.get_double(s, "evidence_cell", evidence_cell);
  evidence_gain = cfg.get_double(s, "evidence_gain", evidence_gain);
  start_sigmas = cfg.get_double(s, "start_sigmas", start_sigmas);
  prior_std_xy = cfg.get_double(s, "prior_std_xy", prior_std_xy);
  prior_std_theta = cfg.get_double(s, "prior_std_theta", prior_std_theta);
  mode_merge_distance = cfg.get_double(s, "mode_merge_distance", mode_merge_distance);
  mode_merge_angle = cfg.get_double(s, "mode_merge_angle", mode_merge_angle);
  min_probability = cfg.get_double(s, "min_probability", min_probability);
  area_check = cfg.get_bool(s, "area_check", area_check);
  area_check_keyframes = cfg.get_int(s, "area_check_keyframes", area_check_keyframes);
  const std::string method =
      cfg.get_string(s, "search", search == WideSearch::kBnb ? "bnb" : "lattice");
  require(method == "bnb" || method == "lattice", s, "search", "bnb or lattice");
  search = method == "bnb" ? WideSearch::kBnb : WideSearch::kLattice;
  bnb_step_xy = cfg.get_double(s, "bnb_step_xy", bnb_step_xy);
  bnb_step_theta = cfg.get_double(s, "bnb_step_theta", bnb_step_theta);
  bnb_levels = cfg.get_int(s, "bnb_levels", bnb_levels);
  bnb_separation_xy = cfg.get_double(s, "bnb_separation_xy", bnb_separation_xy);
  bnb_separation_theta = cfg.get_double(s, "bnb_separation_theta", bnb_separation_theta);
  bnb_cache_mb = cfg.get_int(s, "bnb_cache_mb", bnb_cache_mb);
  field_cache_mb = cfg.get_int(s, "field_cache_mb", field_cache_mb);
  bnb_margin = cfg.get_double(s, "bnb_margin", bnb_margin);
  bnb_max_blocks = cfg.get_int(s, "bnb_max_blocks", bnb_max_blocks);
  require(bnb_max_blocks >= 1000, s, "bnb_max_blocks", ">= 1000");
  require(bnb_margin >= 0 && bnb_margin <= 1, s, "bnb_margin", "in [0, 1]");
  require(bnb_step_xy > 0, s, "bnb_step_xy", "> 0");
  // (Headings and costs are packed in 16 and 32 bits in the search.)
  require(bnb_step_theta >= 1e-4, s, "bnb_step_theta", ">= 1e-4");
  require(bnb_levels >= 1 && bnb_levels <= 12, s, "bnb_levels", "in [1, 12]");
  require(bnb_separation_xy >= 0, s, "bnb_separation_xy", ">= 0");
  require(bnb_separation_theta >= 0, s, "bnb_separation_theta", ">= 0");
  require(bnb_cache_mb >= 0, s, "bnb_cache_mb", ">= 0");
  require(field_cache_mb >= 0, s, "field_cache_mb", ">= 0");
  search_step_xy = cfg.get_double(s, "search_step_xy", search_step_xy);
  search_step_theta = cfg.get_double(s, "search_step_theta", search_step_theta);
  search_points = cfg.get_int(s, "search_points", search_points);
  search_max_poses = cfg.get_int(s, "search_max_poses", search_max_poses);
  search_modes = cfg.get_int(s, "search_modes", search_modes);
  bound_boxes = cfg.get_int(s, "bound_boxes", bound_boxes);
  require(area_check_keyframes >= 1, s, "area_check_keyframes", ">= 1");
  require(search_step_xy > 0, s, "search_step_xy", "> 0");
  require(search_step_theta > 0, s, "search_step_theta", "> 0");
  require(search_points >= 10 && search_points <= 100000, s, "search_points",
          "in [10, 100000]");
  require(search_max_poses >= 1000, s, "search_max_poses", ">= 1000");
  require(search_modes >= 1 && search_modes <= 100, s, "search_modes", "in [1, 100]");
  require(bound_boxes >= 0, s, "bound_boxes", ">= 0 (0: off)");
  require(std::isfinite(log_eta), s, "log_eta", "finite");
  require(min_match_ratio > 0 && min_match_ratio <= 1, s, "min_match_ratio", "in (0, 1]");
  require(min_points_explained > 0 && min_points_explained <= 1, s, "min_points_explained",
          "in (0, 1]");
  require(max_points_contradicted >= 0 && max_points_contradicted <= 1, s,
          "max_points_contradicted", "in [0, 1]");
  require(free_probability > 0 && free_probability < 0.5, s, "free_probability", "in (0, 0.5)");
  require(gate > 0, s, "gate", "> 0");
  require(max_points >= 10, s, "max_points", ">= 10");
  require(evidence_cell >= 0 && evidence_cell <= 100, s, "evidence_cell", "in [0, 100] (0: off)");
  require(evidence_gain > 0 && std::isfinite(evidence_gain), s, "evidence_gain", "> 0");
  require(start_sigmas >= 0 && start_sigmas <= 5, s, "start_sigmas", "in [0, 5]");
  require(prior_std_xy > 0, s, "prior_std_xy", "> 0");
  require(prior_std_theta > 0, s, "prior_std_theta", "> 0");
  require(mode_merge_distance > 0, s, "mode_merge_distance", "> 0");
  require(mode_merge_angle > 0, s, "mode_merge_angle", "> 0");
  require(min_probability >= 0 && min_probability < 0.5, s, "min_probability",
          "in [0, 0.5)");
}

}  // namespace hmt::tsbi
