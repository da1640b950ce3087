// Scan-to-map matching on an occupancy grid (the likelihood field model).
//
// The distance from an end point to the nearest occupied cell is searched in
// a small window of cells around it, using each cell's mean hit position for
// sub-cell precision; a cell only counts as the wall hit if the probe one
// cell nearer the sensor is not occupied (the beam must arrive from free
// space). Beams with no occupied cell in the window get the window's maximum
// distance: the field is truncated there, which makes the model robust to
// unmapped or dynamic obstacles.
#pragma once

#include <Eigen/Core>

#include "hmt/common/config.h"
#include "hmt/common/pose2d.h"
#include "hmt/grid/occupancy_grid.h"
#include "hmt/metric_slam/scan_points.h"

namespace hmt::metric_slam {

// The widest search window (cells) the matcher accepts.
constexpr int kMaxWindow = 5;

struct MatcherOptions {
  double max_range = 20.0;          // beams longer than this are not matched
  // `max_range = auto` in the configuration (the default): max_range is
  // derived from the log's ranges when it is read (matching_range.h); until
  // then it holds the rule's floor, kMinMatchingRange.
  bool range_from_scans = true;
  int beam_skip = 0;                // use every (skip+1)-th beam
  int window = 1;                   // search radius in cells
  double sigma = 0.05;              // likelihood field std dev (m)
  double occupied_probability = 0.6;  // a cell above this is an obstacle
  double linear_step = 0.05;        // initial hill-climbing steps
  double angular_step = 0.05;
  int refinements = 3;              // step halvings
  // The hill climbing runs on at most this many evenly spread beams, with
  // a wider search window (a wider basin for bad odometry, at the cost of
  // fewer beams); the result is then refined by Gauss-Newton on every beam.
  int coarse_beams = 40;
  int coarse_window = 2;            // search radius (cells) while hill climbing
  int gauss_newton_iterations = 3;
  double min_match_ratio = 0.2;     // below: matching failed, use odometry

  // Whether a match in which `matched` of `beams` beams found an obstacle
  // is one to track by (min_match_ratio of them).
  bool tracks(int matched, size_t beams) const {
    return matched >= min_match_ratio * static_cast<double>(beams);
  }

  void load(Config& cfg, const std::string& section = "scan_matcher");
};

// A scan made ready for ScanMatcher::optimize() once, for any number of
// matches from any starts in any maps: its points, the evenly spread subset
// the hill climbing runs on (coarse_beams) and the range of its far points
// (far_range()).
class MatchScan {
 public:
  MatchScan(ScanPoints points, const MatcherOptions& opt);
  const ScanPoints& points() const { return points_; }
  const ScanPoints& coarse() const { return coarse_; }
  double far() const { return far_; }

 private:
  ScanPoints points_, coarse_;
  double far_;
};

struct MatchScore {
  double log_likelihood = 0.0;  // sum over beams of -d^2 / (2 sigma^2)
  int matched = 0;              // beams with an obstacle in the window
};

class ScanMatcher {
 public:
  explicit ScanMatcher(const MatcherOptions& opt);

  MatchScore score(const grid::OccupancyGrid& map, const Pose2D& pose,
                   const ScanPoints& scan) const;

  // score() of up to kMaxSameHeading poses that share one heading (the
  // proposal's lattice: 9 translations per heading), each to the bit. A
  // beam whose end point and probe fall in the cells they fell in for an
  // earlier pose reuses that pose's obstacles instead of reading the grid.
  static constexpr size_t kMaxSameHeading = 9;
  void score_same_heading(const grid::OccupancyGrid& map, const Pose2D* poses, size_t n,
                          const ScanPoints& scan, MatchScore* out) const;

  // Hill climbing from `start` (GMapping-style: try +-x, +-y, +-theta, take
  // the best, halve the steps when nothing improves) on a subset of beams,
  // then Gauss-Newton on all beams against the matched cells' hit means.
  // When the scan's far points leave a heading basin narrower than half the
  // hill climbing's last angular step (steps_over_heading_basin()), a second
  // climb starts from the best heading of a sweep at the basin's width, and
  // the higher scoring climb is refined.
  // `information` (if given) gets the Gauss-Newton Hessian of
  // -log p(z|x,m) at the result, J^T J / sigma^2 over the beams matched
  // there (point-to-hit-mean residuals): how sharply the scan pins the pose
  // down. The last Gauss-Newton pass has already summed it.
  // `start_error` (m): how far the start may be from the true pose (a
  // filter step's odometry error). Where it lies beyond what the climb
  // reaches by itself (twice its window's reach), a climb at the window
  // that reaches it (window_reaching()) and one at the coarse window from
  // where that ended compete with the climb from the start: the higher
  // scoring wins.
  Pose2D optimize(const grid::OccupancyGrid& map, const Pose2D& start,
                  const MatchScan& scan, MatchScore* best,
                  Eigen::Matrix3d* information = nullptr, double start_error = 0.0) const;
  // The same for a scan matched once (made ready here).
  Pose2D optimize(const grid::OccupancyGrid& map, const Pose2D& start,
                  const ScanPoints& scan, MatchScore* best,
                  Eigen::Matrix3d* information = nullptr) const;

  // The hill climbing's last (finest) angular and linear steps.
  double finest_angular_step() const;
  double finest_linear_step() const;
  // The heading error that moves a point at range `far` by the reach of a
  // search window of `window` cells: beyond it the point finds no obstacle
  // and no longer guides the match. A scan's basin is that of its far points
  // (far_range()), which pin the heading down most sharply.
  static double heading_basin(double far, int window, double resolution);
  // The least window (cells, at most kMaxWindow) whose reach, (window + 0.5)
  // cells, is at least `distance`.
  static int window_reaching(double distance, double resolution);
  // Whether the basin (at the hill climbing's window) of a scan whose far
  // points lie at `far` is narrower than half the climb's last angular step.
  // A move of that step then lands outside the basin from any side, so the
  // climb keeps the heading it started from: outdoor scans, whose returns
  // lie tens of metres away. Indoors (points within 20 m, 5 cm cells) the
  // basin is at least half the default last step, and this is false.
  bool steps_over_heading_basin(double far, double resolution) const;

  // How much lower the log-likelihood of a beam with no obstacle in the
  // window is than that of a beam on an obstacle: the most one beam can tell
  // two poses apart by.
  double unmatched_beam_cost(double resolution) const;

  const MatcherOptions& options() const { return opt_; }
  // A cell at or above this log-odds is an obstacle to match against.
  grid::LogOdds occupied_threshold() const { return occ_threshold_; }

 private:
  // The last step of a hill climbing that starts with steps of `first`.
  double finest_step(double first) const;
  // The score with window radius `window`; once the scan can no longer
  // score above `limit`, it stops and returns the lowest log-likelihood.
  MatchScore score(const grid::OccupancyGrid& map, const Pose2D& pose,
                   const ScanPoints& scan, int window, double limit) const;
  // Scores the headings start.theta +- k * basin (k = 1, 2, ...) out to the
  // hill climbing's last angular step, at start's position, and returns the
  // best pose (start unless one scores higher).
  Pose2D sweep_heading(const grid::OccupancyGrid& map, const Pose2D& start,
                       const ScanPoints& scan, int window, double basin) const;
  // The climb's result, and in *score its score (window `window`).
  Pose2D hill_climb(const grid::OccupancyGrid& map, const Pose2D& start,
                    const ScanPoints& scan, int window, double* score) const;
  // J^T J and J^T r of the point-to-hit-mean residuals at `pose`, and the
  // score there, in one pass; returns the number of matched beams.
  int normal_equations(const grid::OccupancyGrid& map, const ScanPoints& scan,
                       const Pose2D& pose, Eigen::Matrix3d* H, Eigen::Vector3d* g,
                       MatchScore* score_out) const;
  // One Gauss-Newton step from the normal equations at *pose; false if too
  // few matches or a degenerate H leave the pose unconstrained.
  static bool gauss_newton_step(const Eigen::Matrix3d& H, const Eigen::Vector3d& g,
                                int matched, Pose2D* pose);
  // Calls f(i, hx, hy, d2, mean) for every beam i, in order, whose end point
  // (hx, hy) at `pose` has an obstacle in the window; `mean` is the nearest
  // hit mean, d2 its squared distance. f returns false to stop.
  template <class F>
  void for_each_match(const grid::OccupancyGrid& map, const Pose2D& pose,
                      const ScanPoints& scan, int window, F&& f) const;
  template <int W>
  void score_same_heading_in(const grid::OccupancyGrid& map, const Pose2D* poses, size_t n,
                             const ScanPoints& scan, MatchScore* out) const;
  template <int W, class F>
  void for_each_match_in(const grid::OccupancyGrid& map, const Pose2D& pose,
                         const ScanPoints& scan, F& f) const;

  MatcherOptions opt_;
  grid::LogOdds occ_threshold_;
  double inv_2sigma2_;
};

}  // namespace hmt::metric_slam
