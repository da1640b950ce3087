#include "hmt/islands/islands_options.h"

#include <cmath>

namespace hmt::islands {
namespace {

bool positive(double v) { return std::isfinite(v) && v > 0.0; }

}  // namespace

void IslandsOptions::load(Config& cfg, const std::string& s) {
  wall_probability = cfg.get_double(s, "wall_probability", wall_probability);
  rays = cfg.get_int(s, "rays", rays);
  field_of_view = cfg.get_double(s, "field_of_view", field_of_view);
  headings = cfg.get_int(s, "headings", headings);
  max_range = cfg.get_double(s, "max_range", max_range);
  decay = cfg.get_double(s, "decay", decay);
  cutoff = cfg.get_double(s, "cutoff", cutoff);
  rate = cfg.get_double(s, "rate", rate);
  epsilon = cfg.get_double(s, "epsilon", epsilon);
  stride = cfg.get_int(s, "stride", stride);
  normal_radius = cfg.get_double(s, "normal_radius", normal_radius);
  reference_window = cfg.get_double(s, "reference_window", reference_window);
  threshold = cfg.get_double(s, "threshold", threshold);
  min_distance = cfg.get_double(s, "min_distance", min_distance);
  threads = cfg.get_int(s, "threads", threads);

  require(std::isfinite(wall_probability) && wall_probability >= 0 && wall_probability < 1, s,
          "wall_probability", "in [0, 1)");
  require(rays >= 4 && rays <= 100000, s, "rays", "in [4, 100000]");
  require(std::isfinite(field_of_view) && field_of_view > 0 && field_of_view <= 360, s,
          "field_of_view", "in (0, 360]");
  require(headings >= 1 && headings <= 3600, s, "headings", "in [1, 3600]");
  require(positive(max_range), s, "max_range", "> 0 and finite");
  require(std::isfinite(decay) && decay >= 0, s, "decay", ">= 0 and finite");
  require(positive(cutoff), s, "cutoff", "> 0 and finite");
  require(positive(rate), s, "rate", "> 0 and finite");
  require(std::isfinite(epsilon) && epsilon >= 0, s, "epsilon", ">= 0 and finite");
  require(stride >= 1 && stride <= 64, s, "stride", "in [1, 64]");
  require(positive(normal_radius), s, "normal_radius", "> 0 and finite");
  require(std::isfinite(reference_window) && reference_window >= 1 && reference_window <= 180,
          s, "reference_window", "in [1, 180]");
  require(std::isfinite(threshold) && threshold >= 0 && threshold <= 1, s, "threshold",
          "in [0, 1]");
  require(std::isfinite(min_distance) && min_distance >= 0, s, "min_distance",
          ">= 0 and finite");
  require(threads >= 0 && threads <= 1024, s, "threads", "in [0, 1024]");
}

}  // namespace hmt::islands
