#include "hmt/grid/scan_insertion.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <vector>

namespace hmt::grid {
namespace {

// Which cells a scan has already updated, over the scan's bounding box: one
// bit per cell for hits and one for free-space updates, so every cell gets
// at most one update per scan.
class UpdateMarks {
 public:
  void reset(CellIndex lo, CellIndex hi) {
    x0_ = lo.x;
    y0_ = lo.y;
    w_ = static_cast<size_t>(hi.x - lo.x + 1);
    const size_t words = (w_ * static_cast<size_t>(hi.y - lo.y + 1) + 63) / 64;
    hit_.assign(words, 0);
    free_.assign(words, 0);
  }
  // Each returns true the first time it marks a cell.
  bool mark_hit(int x, int y) { return mark(hit_, x, y); }
  bool mark_free(int x, int y) { return mark(free_, x, y); }
  bool is_hit(int x, int y) const {
    const size_t i = index(x, y);
    return (hit_[i >> 6] >> (i & 63)) & 1u;
  }

 private:
  size_t index(int x, int y) const {
    return static_cast<size_t>(y - y0_) * w_ + static_cast<size_t>(x - x0_);
  }
  bool mark(std::vector<uint64_t>& bits, int x, int y) {
    const size_t i = index(x, y);
    uint64_t& word = bits[i >> 6];
    const uint64_t bit = uint64_t{1} << (i & 63);
    if (word & bit) return false;
    word |= bit;
    return true;
  }

  int x0_ = 0, y0_ = 0;
  size_t w_ = 0;
  std::vector<uint64_t> hit_, free_;
};

// Walks the cells of a Bresenham line, fetching each tile once per visit.
class RayWriter {
 public:
  RayWriter(OccupancyGrid& g, LogOdds l_free, LogOdds l_clamp, UpdateMarks& marks)
      : grid_(g), l_free_(l_free), l_clamp_(l_clamp), marks_(marks) {}

  // The writable tile of cell (x, y); *index gets the cell's index in it.
  Tile& tile(int x, int y, int* index) {
    const int tx = x >> kTileBits, ty = y >> kTileBits;
    if (!tile_ || tx != tx_ || ty != ty_) {
      tile_ = &grid_.mutable_tile(tx, ty);
      tx_ = tx;
      ty_ = ty;
    }
    *index = OccupancyGrid::index_in_tile({x, y});
    return *tile_;
  }

  // Marks free the cells from a (inclusive) to b (exclusive), walking back
  // from b and stopping at the first cell this scan already updated: all
  // rays start at the sensor, so once this ray meets an earlier one the rest
  // of the way to the sensor has been cleared by it (to within a cell; the
  // few cells that differ are cleared by neighbouring rays or later scans).
  // Near the sensor, where beams crowd together, this walks each cell about
  // once per scan instead of once per beam.
  void free_line(CellIndex a, CellIndex b) {
    int x = b.x, y = b.y;
    const int dx = std::abs(a.x - b.x), dy = -std::abs(a.y - b.y);
    const int sx = b.x < a.x ? 1 : -1, sy = b.y < a.y ? 1 : -1;
    int err = dx + dy;
    bool at_end = true;  // b itself is the hit cell (or the range limit)
    for (;;) {
      // Cells another beam ends in keep their hit (and do not stop the walk).
      if (!at_end && !marks_.is_hit(x, y)) {
        if (!marks_.mark_free(x, y)) return;
        int i;
        LogOdds& l = tile(x, y, &i).logodds[i];
        l = static_cast<LogOdds>(std::max<int>(l + l_free_, -l_clamp_));
      }
      at_end = false;
      if (x == a.x && y == a.y) return;
      const int e2 = 2 * err;
      if (e2 >= dy) { err += dy; x += sx; }
      if (e2 <= dx) { err += dx; y += sy; }
    }
  }

 private:
  OccupancyGrid& grid_;
  LogOdds l_free_, l_clamp_;
  UpdateMarks& marks_;
  Tile* tile_ = nullptr;
  int tx_ = 0, ty_ = 0;
};

}  // namespace

void InsertionOptions::load(Config& cfg, const std::string& s) {
  p_occupied = cfg.get_double(s, "p_occupied", p_occupied);
  p_free = cfg.get_double(s, "p_free", p_free);
  p_clamp = cfg.get_double(s, "p_clamp", p_clamp);
  // A number, or "auto": the matcher's range (set by the options' owner).
  cfg.get_double_or_auto(s, "max_insertion_range", &max_range, &range_from_matcher);
  require(p_occupied > 0.5 && p_occupied < 1.0, s, "p_occupied", "in (0.5, 1)");
  require(p_free > 0.0 && p_free < 0.5, s, "p_free", "in (0, 0.5)");
  require(p_clamp > p_occupied && p_clamp <= 0.998, s, "p_clamp",
          "in (p_occupied, 0.998]");
  require(max_range > 0.0, s, "max_insertion_range", "> 0");
}
LogOdds InsertionOptions::l_occupied() const { return scaled_logit(p_occupied); }
LogOdds InsertionOptions::l_free() const { return scaled_logit(p_free); }
LogOdds InsertionOptions::l_clamp() const { return scaled_logit(p_clamp); }

void insert_scan(OccupancyGrid& grid, const Pose2D& robot_pose,
                 const LaserScan& scan, const InsertionOptions& opt) {
  // Each cell is updated at most once per scan (as in Cartographer's
  // update markers): near the sensor hundreds of beams cross the same cells,
  // and one scan is one observation of them, not hundreds. Hits go first, so
  // a cell some beam ends in is not also cleared by a neighbouring beam.
  const LogOdds l_occ = opt.l_occupied(), l_clamp = opt.l_clamp();
  const Pose2D sensor = robot_pose + scan.sensor_pose;
  const CellIndex origin = grid.cell_of(sensor.x, sensor.y);
  const double res = grid.resolution();

  struct Beam {
    CellIndex end;
    double ex, ey;
    bool hit;
  };
  std::vector<Beam> beams;
  beams.reserve(scan.size());
  CellIndex lo = origin, hi = origin;
  for (size_t i = 0; i < scan.size(); ++i) {
    if (!scan.valid[i]) continue;
    const double r = scan.ranges[i];
    const bool hit = r <= opt.max_range;
    const double rr = hit ? r : opt.max_range;
    const double a = sensor.theta + scan.bearing(i);
    const double ex = sensor.x + rr * std::cos(a), ey = sensor.y + rr * std::sin(a);
    const CellIndex end = grid.cell_of(ex, ey);
    lo = {std::min(lo.x, end.x), std::min(lo.y, end.y)};
    hi = {std::max(hi.x, end.x), std::max(hi.y, end.y)};
    beams.push_back({end, ex, ey, hit});
  }
  thread_local UpdateMarks marks;
  marks.reset(lo, hi);
  RayWriter ray(grid, opt.l_free(), l_clamp, marks);
  const double k = kHitScale / res;
  for (const Beam& b : beams) {
    if (!b.hit) continue;
    const bool first = marks.mark_hit(b.end.x, b.end.y);
    int i;
    Tile& t = ray.tile(b.end.x, b.end.y, &i);
    if (first) t.logodds[i] = static_cast<LogOdds>(std::min<int>(t.logodds[i] + l_occ, l_clamp));
    HitMean& c = t.mutable_hit(i);
    // Running mean of the hit positions inside the cell (every hit counts;
    // the weight is capped so the mean still follows small changes).
    const Point2D ctr = grid.cell_center(b.end);
    const int px = static_cast<int>(std::lround((b.ex - ctr.x) * k));
    const int py = static_cast<int>(std::lround((b.ey - ctr.y) * k));
    const int n = std::min<int>(c.hits + 1, 16);
    c.hx = static_cast<int8_t>(std::clamp(c.hx + (px - c.hx) / n, -127, 127));
    c.hy = static_cast<int8_t>(std::clamp(c.hy + (py - c.hy) / n, -127, 127));
    if (c.hits < 255) ++c.hits;
  }
  for (const Beam& b : beams) ray.free_line(origin, b.end);
}

}  // namespace hmt::grid
