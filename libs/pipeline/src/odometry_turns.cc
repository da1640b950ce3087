#include "odometry_turns.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "hmt/common/error.h"
#include "hmt/grid/occupancy_grid.h"
#include "hmt/grid/scan_insertion.h"
#include "hmt/metric_slam/scan_points.h"

namespace hmt::pipeline {
namespace {

constexpr double kResolution = 0.05;  // m: the default grid's cells
constexpr double kRange = 20.0;       // m: the default matching range

metric_slam::MatcherOptions sweep_options() {
  metric_slam::MatcherOptions o;
  o.window = o.coarse_window;  // the climb's basin: a start 1.4 degrees off climbs in
  return o;
}

}  // namespace

OdometryTurnsCheck::OdometryTurnsCheck()
    : matcher_(metric_slam::MatcherOptions{}), sweep_(sweep_options()) {}

void OdometryTurnsCheck::add(const LogStep& step, size_t index, const std::string& source) {
  if (decisive_ >= kTurns || checked_ >= kMaxChecks) return;
  if (!reference_) {
    reference_ = step.scan;
    moved_ = Pose2D();
    return;
  }
  moved_ = moved_ + step.odometry_increment;
  if (std::hypot(moved_.x, moved_.y) > kMaxShift) {
    reference_ = step.scan;
    moved_ = Pose2D();
    return;
  }
  if (std::fabs(moved_.theta) < kMinTurn) return;
  ++checked_;
  check(step.scan, moved_);
  reference_ = step.scan;
  moved_ = Pose2D();
  if (decisive_ < kTurns || 2 * disagreed_ < decisive_) return;
  char m[320];
  std::snprintf(m, sizeof m,
                "the odometry's turns disagree with the laser's at %zu of the first %zu clear "
                "turns (by up to %.2f rad): at each the laser explains its scan at least %.2f "
                "times better at a heading more than %.1f rad from the odometry's",
                disagreed_, decisive_, worst_, kClearly, kAgree);
  throw InputError("log '" + source + "' step " + std::to_string(index) + ": " + m +
                   " (headings in degrees, a left-handed odometry frame, or a laser mounted "
                   "upside down: its beams in the reverse order?)");
}

void OdometryTurnsCheck::check(const LaserScan& scan, const Pose2D& odometry) {
  grid::OccupancyGrid map(kResolution);
  grid::InsertionOptions ins;
  ins.max_range = kRange;
  grid::insert_scan(map, Pose2D(), *reference_, ins);
  const metric_slam::MatchScan ready(metric_slam::prepare_scan(scan, kRange, 0, kResolution),
                                     matcher_.options());
  const size_t beams = ready.points().hit.size();
  if (beams == 0) return;
  // Every heading scored at the odometry's position; the best near the
  // odometry's heading and the best few elsewhere are climbed from.
  struct Start {
    double score;
    Pose2D pose;
    bool near;
  };
  std::vector<Start> starts;
  for (int k = 0; k < kHeadings; ++k) {
    const double dt = wrap_angle(2.0 * M_PI * k / kHeadings);
    const Pose2D p(odometry.x, odometry.y, wrap_angle(odometry.theta + dt));
    starts.push_back({sweep_.score(map, p, ready.coarse()).log_likelihood, p,
                      std::fabs(dt) <= kAgree});
  }
  std::stable_sort(starts.begin(), starts.end(),
                   [](const Start& a, const Start& b) { return a.score > b.score; });
  int near_best = -1, far_best = -1;
  double far_off = 0.0;  // the far climb's heading from the odometry's
  const auto climb = [&](const Start& s) {
    metric_slam::MatchScore sc;
    const Pose2D p = matcher_.optimize(map, s.pose, ready, &sc);
    // Where the climb ended decides near or far, not where it started.
    const double off = std::fabs(wrap_angle(p.theta - odometry.theta));
    if (off <= kAgree) {
      near_best = std::max(near_best, sc.matched);
    } else if (sc.matched > far_best) {
      far_best = sc.matched;
      far_off = off;
    }
  };
  climb({0.0, odometry, true});
  int climbed_near = 0, climbed_far = 0;
  for (const Start& s : starts) {
    int& n = s.near ? climbed_near : climbed_far;
    if (n >= 3) continue;
    ++n;
    climb(s);
  }
  const double need = kDecisive * static_cast<double>(beams);
  if (std::max(near_best, far_best) < need) return;
  ++decisive_;
  if (far_best >= kClearly * std::max(near_best, 0)) {
    ++disagreed_;
    worst_ = std::max(worst_, far_off);
  }
}

}  // namespace hmt::pipeline
