#include "hmt/area/area_size.h"

#include <algorithm>
#include <cmath>

namespace hmt::area {
namespace {

// The fraction of the field of view two scans share when their headings
// differ by d (radians, circular distance in [0, pi]).
double overlap(double d, double fov) {
  const double shared = std::max(0.0, fov - d) + std::max(0.0, fov - (2.0 * M_PI - d));
  return std::min(shared, fov) / fov;
}

double circular_distance(double a, double b) {
  const double d = std::fabs(a - b);
  return std::min(d, 2.0 * M_PI - d);
}

}  // namespace

double place_ncut(double fov) {
  fov = std::min(fov, 2.0 * M_PI);
  // Midpoint rule over the two heading halves [0, pi) and [pi, 2 pi): the
  // overlap is piecewise linear in the headings, so a fine grid is exact to
  // well below the precision tau needs.
  constexpr int kSteps = 360;
  const double h = M_PI / kSteps;
  double within = 0.0, across = 0.0;
  for (int i = 0; i < kSteps; ++i) {
    const double a = (i + 0.5) * h;
    for (int j = 0; j < kSteps; ++j) {
      const double b = (j + 0.5) * h;
      within += overlap(circular_distance(a, b), fov);
      across += overlap(circular_distance(a, b + M_PI), fov);
    }
  }
  return 2.0 * across / (within + across);
}

double tau_for_field_of_view(double fov) { return kTauMargin * place_ncut(fov); }

double field_of_view(const LaserScan& scan) {
  return std::min(2.0 * M_PI, std::fabs(static_cast<double>(scan.angle_increment)) *
                                  static_cast<double>(scan.size()));
}

bool resolve_tau(AreaOptions& options, const LaserScan& scan) {
  if (!options.partition.tau_from_sensor) return false;
  const double fov = field_of_view(scan);
  if (scan.size() < 2 || !(fov > 0.0)) return false;
  options.partition.tau = tau_for_field_of_view(fov);
  return true;
}

bool resolve_tau(AreaOptions& options, const Log& log) {
  for (const LogStep& s : log.steps)
    if (resolve_tau(options, s.scan)) return true;
  return false;
}

}  // namespace hmt::area
