// Options of the metric RBPF grid SLAM filter; each group has its own INI
// section: [metric_slam], [grid], [scan_matcher], [motion_model].
#pragma once

#include <cstdint>
#include <string>

#include "hmt/common/config.h"
#include "hmt/grid/scan_insertion.h"
#include "hmt/metric_slam/motion_model.h"
#include "hmt/metric_slam/scan_matcher.h"

namespace hmt::metric_slam {

enum class ProposalKind { kOptimal, kOdometry };

struct RbpfOptions {
  int particles = 30;
  uint64_t seed = 1;
  int threads = 0;  // worker threads; 0 = one per core
  ProposalKind proposal = ProposalKind::kOptimal;
  double resample_threshold = 0.5;  // resample when ESS < this * particles
  // The filter runs on a scan only once the odometry says the robot moved
  // this far (less half the scan's own step: the scan nearest the mark) or
  // turned this much since the last filtered scan (scans a few centimetres
  // apart would weigh the particles by the same evidence again and again:
  // config/default.ini).
  double update_distance = 0.5;
  double update_angle = 0.05;
  // A particle inserts a scan into its map only after moving this far since
  // its last insertion (both 0: every scan).
  double map_update_distance = 0.2;
  double map_update_angle = 0.1;
  // Log-likelihoods are divided by this before weighting: beams are not
  // independent, and an untempered product makes the weights collapse.
  double likelihood_gain = 30.0;
  // The same for the likelihood that shapes the proposal Gaussian.
  double proposal_gain = 1.0;
  // Half-widths of the 3x3x3 lattice around the scan-match mode on which the
  // optimal proposal is evaluated (paper 002 Eq. 6, second step).
  double sample_linear = 0.02;
  double sample_angular = 0.01;
  // The lattice uses at most this many evenly spread beams (0 = all).
  int lattice_beams = 60;
  // When the scan match started from the odometry explains fewer than
  // heading_search_ratio of the beams, the odometry's heading may be far off
  // (a fast turn, a slipping wheel): the match is also started from headings
  // up to heading_search_range (rad) either side, 2 x [scan_matcher]
  // angular_step apart (the hill climbing's basin), and the mode of
  // likelihood x motion prior among the results in another basin than the
  // first match's is kept if it beats it. 0 for either: off.
  double heading_search_ratio = 0.5;
  double heading_search_range = 0.5;

  double resolution = 0.05;
  grid::InsertionOptions insertion;
  MatcherOptions matcher;
  MotionOptions motion;

  void load(Config& cfg);
};

}  // namespace hmt::metric_slam
