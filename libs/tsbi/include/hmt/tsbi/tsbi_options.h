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
  // the observation points that fall within the area's extent (the bounds
  // of the cells its map observed). Points beyond it are seen from places
  // the map never covered: no pose of that map could explain them, and they
  // say nothing against it (outdoors, a return at an area's edge sees far
  // past what the area mapped).
  double min_match_ratio = 0.6;
  // ... and at least this fraction of all the points: a return must overlap
  // the area for most of what it sees.
  double min_points_explained = 0.5;
  // ... and at most this fraction of the points may lie on a surface (a
  // group of them spanning 1 m) where the map saw clear free space (their
  // cell and every cell within the matcher's window known and at most
  // free_probability occupied): where the map saw through, a right match
  // sees no wall; a person standing there is no surface. 1: no such limit.
  double max_points_contradicted = 0.08;
  double free_probability = 0.35;
  // ... and lies inside the prior: squared Mahalanobis distance to the
  // prior mean below this (chi-square, 3 dof: 16.27 is the 99.9% quantile).
  double gate = 16.27;
  // The observations are at most this many points (evenly spread).
  int max_points = 600;
  // How much the observations weigh. Returns from one patch of surface (a
  // near wall hit by many beams, the overlap of the new area's keyframes)
  // are one piece of evidence, not many: the log-likelihood of the points
  // kept stands for the number of distinct evidence_cell x evidence_cell
  // cells (m) the returns fall in, divided by evidence_gain. Intel's events
  // hold 8.7 returns a 0.25 m cell, so 30 / 8.7 = 3.5 gives them the weight
  // they had with every return counted and tempered by [metric_slam]
  // likelihood_gain (30); the simulated campus's long-range 180-degree scans
  // hold 5.3 a cell, and its loops close (docs/measurements.md).
  // evidence_cell 0: every return counts, tempered by likelihood_gain.
  // The caller gathers the observations with it (gather_observations()),
  // and they carry it to the model.
  double evidence_cell = 0.25;
  double evidence_gain = 3.5;
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
  // Wide search for the modes: when the prior is broad, candidate poses
  // over the prior's gate are scored first (on a subset of points, with a
  // wide window; the score of cost_stack.h) and the best distinct maxima
  // are refined. Two ways:
  //  - kBnb: the exact best of every pose of a fine lattice in the gate, by
  //    branch and bound (bnb_matcher.h), whatever the gate's size;
  //  - kLattice: the best poses of a lattice over the gate, coarsened to at
  //    most search_max_poses poses (a wide gate gets coarse steps and can
  //    miss the true pose).
  enum class WideSearch { kBnb, kLattice };
  WideSearch search = WideSearch::kBnb;
  // 200 points separate the right place from a look-alike better than 80.
  int search_points = 200;
  int search_modes = 8;              // maxima refined
  // Lattice: steps before coarsening, and the cap.
  double search_step_xy = 0.2;       // [m]
  double search_step_theta = 0.03;   // [rad]
  int search_max_poses = 50000;
  // Branch and bound: the lattice's steps (the translation in whole cells);
  // blocks of up to 2^(bnb_levels-1) steps a side; maxima closer than the
  // separation (in x, y and heading) to a better one are not refined; the
  // per-map cost stacks are cached up to bnb_cache_mb.
  double bnb_step_xy = 0.05;          // [m]
  double bnb_step_theta = 0.01;       // [rad]
  int bnb_levels = 6;
  double bnb_separation_xy = 0.3;     // [m]
  double bnb_separation_theta = 0.1;  // [rad]
  // Maxima are refined only if their cost is within this fraction of the
  // points' saturated cost of the best one's (a look-alike must score
  // nearly as well to matter; the weak maxima cost most of the search).
  double bnb_margin = 0.1;
  // A search stops after bounding this many blocks of poses (about 0.3 s),
  // with the maxima found by then: the cost of one event stays bounded
  // where the bound cannot prune (long look-alike corridors).
  int bnb_max_blocks = 1000000;
  int bnb_cache_mb = 8;
  // The match fields are cached up to field_cache_mb (least recently used
  // rebuilt beyond): fields are rebuilt identically, so results never
  // depend on it.
  int field_cache_mb = 16;
  // Before matching, a branch and bound proves for most hopeless areas that
  // no pose in the gate lets min_points_explained of the points reach an
  // obstacle (match_field.h); it gives up (and the area is matched) after
  // this many boxes of poses. 0: never skip an area.
  int bound_boxes = 5000;
  // Outcomes less probable than this are dropped (and the rest
  // renormalised); a known area with F below this times eta is no outcome.
  double min_probability = 1e-3;

  void load(Config& cfg, const std::string& section = "tsbi");
};

}  // namespace hmt::tsbi
