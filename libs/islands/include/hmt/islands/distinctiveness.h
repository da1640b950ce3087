// The distinctiveness measure R of Simhon & Dudek (003, Eq. 2 and 4-12) over
// an occupancy grid of a laser range map, in place of the paper's sonar line
// segments:
//
//  - From a free cell p the sensor's rays are cast into the grid (a DDA walk,
//    up to max_range; occupied cells are hits, unknown cells end a ray
//    unseen, uncertain ones let it through: occupancy_raster.h). Each hit contributes a
//    vector influence (Eq. 7) along the surface normal at the hit
//    (surface_normals.h), of length W(d) |N . view| dTheta, with W(d) =
//    exp(-k d) (Eq. 8). The part of a hit that is not wall-like (its
//    isotropy) contributes W(d) dTheta along the viewing direction instead.
//  - The reference vector is the largest surface's influence: the hits whose
//    normals lie within reference_window of one another, as the paper's line
//    segment, the window holding the most influence, its direction their
//    mean axis. C_par and C_perp (Eq. 9-10) sum |V_ref . V_i| and |V_ref x
//    V_i| over every hit.
//  - Both are remapped by the sigmoid of Eq. 11; Q (Eq. 12) is the ratio of
//    the remapped values (the smaller over the larger, 0 when both are 0),
//    F = min of them (Eq. 5), and each cell's term F (1 + Q) / 2.
//  - R(p, epsilon) is that term averaged over the free cells of the (2
//    epsilon)^2 square around p (Eq. 4 with the normalisation of Eq. 6 taken
//    over the free cells, where a robot can be), with a summed-area table.
//
// The terms are evaluated at every stride-th cell along x and y; R at a cell
// averages the evaluated ones in its square, the square widened to at least
// stride / 2 cells each side so that every free cell has one when the
// lattice point near it is free. Cells are independent: rows are shared
// among threads and the result does not depend on their number.
#pragma once

#include <cstdint>
#include <vector>

#include "hmt/islands/islands_options.h"
#include "hmt/islands/occupancy_raster.h"

namespace hmt::islands {

// Eq. 11: C^m / (c^m + C^m) (0 for C <= 0).
double sigmoid(double value, double cutoff, double rate);
// Eq. 12: the smaller of the two over the larger, in [0, 1]; 0 if both are 0.
double quality(double c_parallel, double c_perp);

// One vector influence (Eq. 7) along an axis: the unit vector (ux, uy) up to
// sign, and its length.
struct Influence {
  double ux = 1.0;
  double uy = 0.0;
  double magnitude = 0.0;
};

struct Constraints {
  double parallel = 0.0;  // C_par (Eq. 9), before the sigmoid
  double perp = 0.0;      // C_perp (Eq. 10)
  double ref_x = 1.0;     // the reference direction
  double ref_y = 0.0;
};
// Eq. 9-10 with the reference chosen as above (window in radians).
Constraints constraints(const std::vector<Influence>& influences, double window);

// A cell's values (the heading that scored best, with a field of view under
// 360 degrees).
struct CellTerms {
  float c_parallel = 0.0f;  // before the sigmoid
  float c_perp = 0.0f;
  float f = 0.0f;  // Eq. 5 on the remapped values
  float q = 0.0f;  // Eq. 12
  float term() const { return f * (1.0f + q) * 0.5f; }
};

struct DistinctivenessMap {
  int width = 0;
  int height = 0;
  int stride = 1;
  // Per raster cell (row-major, row 0 the bottom): R in [0, 1], NaN where
  // there is none (not free, or no evaluated cell around).
  std::vector<float> r;
  // Per evaluated cell: its index in the raster and its terms.
  std::vector<size_t> evaluated;
  std::vector<CellTerms> terms;
};

DistinctivenessMap distinctiveness(const OccupancyRaster& map, const IslandsOptions& options);

// The terms at one free cell (what distinctiveness() evaluates), for tests
// and probes. Normals from surface_normals(map, normal_radius / resolution).
CellTerms cell_terms(const OccupancyRaster& map, int i, int j, const IslandsOptions& options);

}  // namespace hmt::islands
