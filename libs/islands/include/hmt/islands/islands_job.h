// The `hmt-slam islands` job: R over a map (map_input.h), the islands chosen
// from it, and what a user reads, written into the output folder:
//   distinctiveness.png   R as a heat map over the map, with a colour bar
//                         (0 to 1) and the islands (heat_map.h)
//   islands.png           the grey map with the islands and their ids
//   distinctiveness.pgm   R per cell, grey level round(254 R), 255 where
//   + .yaml               there is none (walls, unknown space); the .yaml
//                         places it as the map is placed
//   distinctiveness.csv   x,y,c_parallel,c_perp,F,Q,term,R per evaluated
//                         cell (map frame, metres; C before the sigmoid)
//   islands.csv           id,x,y,R of each island
//   islands.json          what was read, the cell counts, the time taken and
//                         the islands
// and with a check (localization_check.h):
//   localization_check.csv  x,y,heading,R,error_xy,error_theta per sample,
//                         and islands.json's "check": samples, Spearman's
//                         rank correlation of R and the error, error quantiles
// All written atomically.
#pragma once

#include <string>
#include <vector>

#include "hmt/islands/island_choice.h"
#include "hmt/islands/islands_options.h"
#include "hmt/islands/localization_check.h"

namespace hmt::islands {

struct IslandsSummary {
  std::string map_description;
  int width = 0;
  int height = 0;
  size_t free_cells = 0;
  size_t evaluated_cells = 0;
  double compute_time_s = 0.0;  // R alone
  double mean_r = 0.0;          // over the cells that have one
  std::vector<Island> islands;
  bool checked = false;
  CheckResult check;
};

// What the localization check needs besides its own options: the matcher
// and the log-odds of a run's configuration.
struct CheckSetup {
  CheckOptions options;
  metric_slam::MatcherOptions matcher;
  grid::InsertionOptions insertion;
};

// `check`: null, or run the localization check too.
IslandsSummary run_islands_job(const std::string& map_path, const IslandsOptions& options,
                               const std::string& out_dir, const CheckSetup* check = nullptr);

}  // namespace hmt::islands
