// Where a new area starts: the island-placement criterion of Simhon & Dudek
// (003, Eq. 3) beside the SSO normalized cut of the area abstraction.
//
// Eq. 3 starts a node (here: an area) where
//     epsilon > E_min   and   max_i R_i / T_i > E_min / epsilon,
// epsilon being the robot's accumulated error, R_i the distinctiveness of the
// place for model type i and T_i that model's acceptance threshold: once the
// robot is "lost" it takes a reliable enough place, the more readily the more
// lost it is.
//
// R of a place is computed from the keyframe's own scan rather than from a
// grid (the islands tool's distinctiveness.h evaluates R over an occupancy
// raster): the scan is what the robot senses at the place, needs no map of the
// current area, and costs one pass over its beams. Each return is a hit with
// a surface normal (principal axes of the neighbouring returns within
// normal_radius) contributing the vector influence of Eq. 7, W(d) |N . view|
// dTheta along the normal with W(d) = exp(-k d) (Eq. 8), and its non-wall-like
// part (isotropy l2 / l1) W(d) dTheta along the viewing direction. The
// reference vector is the largest surface (the normals within
// reference_window of one another holding the most influence); C_par, C_perp
// (Eq. 9-10) go through the sigmoid of Eq. 11, Q is Eq. 12, F = min (Eq. 5)
// and R = F (1 + Q) / 2, the per-cell term of the islands tool.
#pragma once

#include <string>
#include <vector>

#include "hmt/common/sensor_data.h"

namespace hmt::area {

enum class Placement {
  kSso,      // the SSO normalized cut alone (000 Table 1)
  kIslands,  // Eq. 3 alone decides when a new area starts
  kBoth,     // the cut proposes a split, Eq. 3 must also fire
};

// "sso" / "islands" / "both"; throws ConfigError naming section and key.
Placement parse_placement(const std::string& text, const std::string& section,
                          const std::string& key);
const char* to_string(Placement p);

struct PlacementOptions {
  Placement policy = Placement::kSso;
  // E_min of Eq. 3 [m]: the accumulated position error (standard deviation)
  // above which the robot looks for a place to start a new area.
  double e_min = 0.1;
  // T of Eq. 3 for the one model type (the laser scan's R).
  double threshold = 0.5;
  // The scan's R (see the header comment): k of Eq. 8 [1/m], c and m of the
  // sigmoid of Eq. 11, the normal neighbourhood [m], the reference window
  // [deg] and the range beyond which returns are not used [m].
  double decay = 0.25;
  double cutoff = 0.5;
  double rate = 4.0;
  double normal_radius = 0.25;
  double reference_window = 15.0;
  double max_range = 8.0;
};

// Eq. 3 exactly: epsilon > e_min and max_i r[i] / t[i] > e_min / epsilon.
// r and t have the same length (throws std::invalid_argument otherwise);
// every t[i] > 0.
bool placement_fires(double epsilon, const std::vector<double>& r,
                     const std::vector<double>& t, double e_min);

// R in [0, 1] of the place where `scan` was taken (0 with fewer than two
// usable returns).
double scan_distinctiveness(const LaserScan& scan, const PlacementOptions& options);

}  // namespace hmt::area
