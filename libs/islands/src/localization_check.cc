#include "hmt/islands/localization_check.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numeric>
#include <stdexcept>

#include "hmt/common/files.h"
#include "hmt/common/random.h"
#include "hmt/metric_slam/scan_points.h"

namespace hmt::islands {
namespace {

constexpr double kPi = 3.14159265358979323846;

// The range along the beam from (x, y) (cell units) at `angle` to the first
// occupied cell, in cells; negative when the beam meets unknown space, the
// map's edge or nothing within max_cells (no return). The range is that of
// the point of the beam nearest the cell's centre, where the matcher's grid
// holds the cell's hit (matcher_grid): a range to the cell's near face would
// put every end point half a cell short of its wall, and the matcher would
// pull the pose half a cell towards the walls.
double cast(const OccupancyRaster& map, double x, double y, double angle, double max_cells) {
  const double dx = std::cos(angle), dy = std::sin(angle);
  int i = static_cast<int>(std::floor(x)), j = static_cast<int>(std::floor(y));
  const int sx = dx > 0 ? 1 : -1, sy = dy > 0 ? 1 : -1;
  const double inf = std::numeric_limits<double>::infinity();
  const double ddx = dx != 0 ? 1.0 / std::abs(dx) : inf, ddy = dy != 0 ? 1.0 / std::abs(dy) : inf;
  double tx = dx != 0 ? (dx > 0 ? (i + 1 - x) : (x - i)) * ddx : inf;
  double ty = dy != 0 ? (dy > 0 ? (j + 1 - y) : (y - j)) * ddy : inf;
  for (;;) {
    double t;
    if (tx < ty) {
      t = tx;
      i += sx;
      tx += ddx;
    } else {
      t = ty;
      j += sy;
      ty += ddy;
    }
    if (t > max_cells || !map.inside(i, j)) return -1.0;
    const CellState s = map.at(i, j);
    if (s == CellState::kOccupied) return std::max(t, (i + 0.5 - x) * dx + (j + 0.5 - y) * dy);
    if (s == CellState::kUnknown) return -1.0;
  }
}

std::vector<double> ranks(const std::vector<double>& v) {
  std::vector<size_t> idx(v.size());
  std::iota(idx.begin(), idx.end(), 0);
  std::stable_sort(idx.begin(), idx.end(), [&](size_t a, size_t b) { return v[a] < v[b]; });
  std::vector<double> r(v.size());
  for (size_t k = 0; k < idx.size();) {
    size_t e = k;
    while (e + 1 < idx.size() && v[idx[e + 1]] == v[idx[k]]) ++e;
    const double mean = 0.5 * (k + e) + 1.0;
    for (size_t m = k; m <= e; ++m) r[idx[m]] = mean;
    k = e + 1;
  }
  return r;
}

}  // namespace

void CheckOptions::load(Config& cfg, const std::string& s) {
  samples = cfg.get_int(s, "samples", samples);
  offset_min = cfg.get_double(s, "offset_min", offset_min);
  offset_max = cfg.get_double(s, "offset_max", offset_max);
  angle_offset = cfg.get_double(s, "angle_offset", angle_offset);
  field_of_view = cfg.get_double(s, "field_of_view", field_of_view);
  beams = cfg.get_int(s, "beams", beams);
  max_range = cfg.get_double(s, "max_range", max_range);
  seed = static_cast<uint64_t>(cfg.get_int(s, "seed", static_cast<int>(seed)));
  require(samples >= 1 && samples <= 1000000, s, "samples", "in [1, 1000000]");
  require(std::isfinite(offset_min) && offset_min >= 0, s, "offset_min", ">= 0");
  require(std::isfinite(offset_max) && offset_max >= offset_min, s, "offset_max",
          ">= offset_min");
  require(std::isfinite(angle_offset) && angle_offset >= 0 && angle_offset < 180, s,
          "angle_offset", "in [0, 180)");
  require(std::isfinite(field_of_view) && field_of_view > 0 && field_of_view <= 360, s,
          "field_of_view", "in (0, 360]");
  require(beams >= 2 && beams <= 100000, s, "beams", "in [2, 100000]");
  require(std::isfinite(max_range) && max_range > 0, s, "max_range", "> 0");
}

grid::OccupancyGrid matcher_grid(const OccupancyRaster& map, const grid::InsertionOptions& ins) {
  grid::OccupancyGrid g(map.resolution);
  const grid::LogOdds l = ins.l_clamp();
  for (int j = 0; j < map.height; ++j)
    for (int i = 0; i < map.width; ++i) {
      const CellState s = map.at(i, j);
      if (s == CellState::kOccupied)
        g.set_cell({i, j}, grid::Cell{l, 1, 0, 0});
      else if (s == CellState::kFree)
        g.set_cell({i, j}, grid::Cell{static_cast<grid::LogOdds>(-l), 0, 0, 0});
    }
  return g;
}

double spearman(const std::vector<double>& a, const std::vector<double>& b) {
  if (a.size() != b.size()) throw std::invalid_argument("spearman: sizes differ");
  if (a.size() < 2) return 0.0;
  const std::vector<double> ra = ranks(a), rb = ranks(b);
  const double n = static_cast<double>(a.size()), mean = (n + 1) / 2;
  double sab = 0, saa = 0, sbb = 0;
  for (size_t k = 0; k < a.size(); ++k) {
    sab += (ra[k] - mean) * (rb[k] - mean);
    saa += (ra[k] - mean) * (ra[k] - mean);
    sbb += (rb[k] - mean) * (rb[k] - mean);
  }
  return saa > 0 && sbb > 0 ? sab / std::sqrt(saa * sbb) : 0.0;
}

CheckResult localization_check(const OccupancyRaster& map, const DistinctivenessMap& d,
                               const CheckOptions& opt,
                               const metric_slam::MatcherOptions& matcher_options,
                               const grid::InsertionOptions& insertion) {
  // The grid's frame: cell (i, j) of the raster is cell (i, j) of the grid.
  const grid::OccupancyGrid grid = matcher_grid(map, insertion);
  const metric_slam::ScanMatcher matcher(matcher_options);
  std::vector<size_t> candidates;
  for (size_t k = 0; k < d.r.size(); ++k)
    if (!std::isnan(d.r[k])) candidates.push_back(k);
  CheckResult out;
  if (candidates.empty()) return out;
  Random rng(opt.seed);
  const double res = map.resolution;
  const double fov = opt.field_of_view * kPi / 180.0;
  LaserScan scan;
  scan.angle_min = static_cast<float>(-fov / 2);
  scan.angle_increment = static_cast<float>(fov / (opt.beams - 1));
  scan.max_range = static_cast<float>(opt.max_range);
  for (int s = 0; s < opt.samples; ++s) {
    const size_t c = candidates[static_cast<size_t>(rng.uniform() * candidates.size()) %
                                candidates.size()];
    const int i = static_cast<int>(c % map.width), j = static_cast<int>(c / map.width);
    const Pose2D truth((i + 0.5) * res, (j + 0.5) * res, rng.uniform(-kPi, kPi));
    scan.ranges.assign(static_cast<size_t>(opt.beams), 0.0f);
    scan.valid.assign(static_cast<size_t>(opt.beams), 0);
    for (int b = 0; b < opt.beams; ++b) {
      const double t = cast(map, i + 0.5, j + 0.5, truth.theta + scan.bearing(b),
                            opt.max_range / res);
      if (t < 0) {
        scan.ranges[b] = scan.max_range;
        continue;
      }
      scan.ranges[b] = static_cast<float>(t * res);
      scan.valid[b] = 1;
    }
    const metric_slam::ScanPoints pts =
        metric_slam::prepare_scan(scan, matcher_options.max_range, matcher_options.beam_skip, res);
    const double dir = rng.uniform(-kPi, kPi);
    const double off = rng.uniform(opt.offset_min, opt.offset_max);
    const double dth = rng.uniform(-1.0, 1.0) * opt.angle_offset * kPi / 180.0;
    const Pose2D start(truth.x + off * std::cos(dir), truth.y + off * std::sin(dir),
                       truth.theta + dth);
    metric_slam::MatchScore score;
    const Pose2D est = pts.hit.empty() ? start : matcher.optimize(grid, start, pts, &score);
    CheckSample cs;
    cs.x = map.origin_x + truth.x;
    cs.y = map.origin_y + truth.y;
    cs.heading = truth.theta;
    cs.r = d.r[c];
    cs.error_xy = std::hypot(est.x - truth.x, est.y - truth.y);
    cs.error_theta = std::abs(std::remainder(est.theta - truth.theta, 2 * kPi));
    out.samples.push_back(cs);
  }
  std::vector<double> r, e;
  for (const CheckSample& cs : out.samples) {
    r.push_back(cs.r);
    e.push_back(cs.error_xy);
  }
  out.spearman = spearman(r, e);
  return out;
}

void write_check_csv(const std::string& path, const CheckResult& result) {
  write_file_atomically(path, [&](std::ostream& os) {
    os << "x,y,heading,R,error_xy,error_theta\n";
    char line[160];
    for (const CheckSample& s : result.samples) {
      std::snprintf(line, sizeof line, "%.3f,%.3f,%.4f,%.5f,%.5f,%.5f\n", s.x, s.y, s.heading,
                    s.r, s.error_xy, s.error_theta);
      os << line;
    }
  });
}

}  // namespace hmt::islands
