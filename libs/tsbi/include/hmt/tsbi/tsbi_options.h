// Options of the topological transition model (TSBI), INI section [tsbi].
#pragma once

#include <string>

#include "hmt/common/config.h"

namespace hmt::tsbi {

struct TsbiOptions {
  // log(eta): the (unnormalised) probability of "an unexplored area", 002
  // Sec. IV-A. F(gamma) below is an expected likelihood ratio against
  // observations that nothing explains, so log_eta is the log-odds a known
  // area must beat: a known area whose map explains the latest observations
  // better than exp(log_eta) times the "nothing explains them" baseline,
  // averaged over where the arcs say the robot may be, wins over a new one.
  double log_eta = 8.0;
  // A mode of the match counts only if it explains at least this fraction of
  // the observation points (the rest are seen from places the area's map
  // never covered).
  double min_match_ratio = 0.6;
  // ... and lies inside the prior: squared Mahalanobis distance to the
  // prior mean below this (chi-square, 3 dof: 16.27 is the 99.9% quantile).
  double gate = 16.27;
  // The observations are at most this many points (evenly spread).
  int max_points = 600;
  // Match starts along each principal axis of the prior, at -k, 0, +k
  // standard deviations (27 starts for 1.5).
  double start_sigmas = 1.5;
  // Floors added to the prior covariance (the arcs can be over-confident).
  double prior_std_xy = 0.10;     // [m]
  double prior_std_theta = 0.03;  // [rad]
  // Modes closer than this (in both) are the same mode.
  double mode_merge_distance = 0.10;  // [m]
  double mode_merge_angle = 0.05;     // [rad]
  // Area check: a known area is a candidate only if the latest observations,
  // placed at the mode, would not be cut off from the area's own keyframes
  // by the area abstraction's criterion (the Ncut of {latest, area} is at
  // least [area] tau). Without it, an adjacent area that still sees much of
  // the new one would pass for a return to it.
  bool area_check = true;
  int area_check_keyframes = 60;  // at most this many of the area's, nearest
  // Wide search for the modes: when the prior is broad, candidate poses on a
  // lattice over the prior's gate are scored first (on a subset of points,
  // with a wide window) and the best local maxima are refined.
  double search_step_xy = 0.2;       // [m]
  double search_step_theta = 0.03;   // [rad]
  // Each lattice pose costs one raster lookup per point (match_field.h):
  // 200 points separate the right place from a look-alike better than 80.
  int search_points = 200;
  int search_max_poses = 50000;     // the lattice is coarsened beyond this
  int search_modes = 8;              // maxima refined
  // Before matching, a branch and bound proves for most hopeless areas that
  // no pose in the gate lets min_match_ratio of the points reach an
  // obstacle (match_field.h); it gives up (and the area is matched) after
  // this many boxes of poses. 0: never skip an area.
  int bound_boxes = 5000;
  // Outcomes less probable than this are dropped (and the rest
  // renormalised).
  double min_probability = 1e-3;

  void load(Config& cfg, const std::string& section = "tsbi");
};

}  // namespace hmt::tsbi
