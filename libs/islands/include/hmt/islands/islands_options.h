// Options of the distinctiveness measure and of the island choice, INI
// section [islands] (Simhon & Dudek, "A Global Topological Map formed by
// Local Metric Maps", IROS 1998, sections 5-7: paper 003). Every default is
// documented in config/default.ini, which is where they are read from.
#pragma once

#include <string>

#include "hmt/common/config.h"

namespace hmt::islands {

struct IslandsOptions {
  // The simulated range sensor at a cell: `rays` directions evenly spread
  // over the full circle, of which it sees those within field_of_view
  // (degrees) around its heading, up to max_range metres. With a field of
  // view under 360, F is evaluated for `headings` evenly spread headings and
  // the best kept (the robot can turn to face the best way at an island).
  // A map cell more likely occupied than this is a wall the rays hit,
  // whatever the map's own occupied threshold: the walls of a laser map
  // seen only a few times stay below map_server's 0.65, and a ray must not
  // pass through them.
  double wall_probability = 0.5;
  int rays = 180;
  double field_of_view = 360.0;  // [deg]
  int headings = 8;
  double max_range = 8.0;  // [m]
  // k of Eq. 8, W(d) = exp(-k d): how fast a hit's reliability decays.
  double decay = 0.25;  // [1/m]
  // c and m of the sigmoid of Eq. 11.
  double cutoff = 0.5;
  double rate = 4.0;
  // Epsilon of Eq. 4: R averages over the (2 epsilon)^2 square.
  double epsilon = 0.2;  // [m]
  // F is evaluated at every stride-th cell along x and y (1 = every cell).
  int stride = 1;
  // The surface normal of an occupied cell: the principal axes of the
  // occupied cells within this radius.
  double normal_radius = 0.25;  // [m]
  // Hits whose normals lie within this angle of one another count as one
  // surface when choosing the reference vector (Eq. 9-10), the grid's
  // counterpart of the paper's line segment.
  double reference_window = 15.0;  // [deg]
  // Islands: local maxima of R of at least `threshold`, at least
  // min_distance metres apart.
  double threshold = 0.5;
  double min_distance = 3.0;  // [m]
  // Worker threads (0 = one per core). Results do not depend on it.
  int threads = 0;

  void load(Config& cfg, const std::string& section = "islands");
};

}  // namespace hmt::islands
