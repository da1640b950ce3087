// A 2D occupancy grid stored as square tiles shared copy-on-write.
//
// Why tiles: in a Rao-Blackwellized filter every particle owns a map, but the
// particles descend from common ancestors and their maps differ only where
// they were updated since they split. Copying a grid copies only the table of
// tile pointers; a tile is cloned the first time a shared copy is written.
// With N particles the memory is one map plus the recently changed tiles, not
// N full maps, and resampling costs a pointer copy per tile.
//
// Each cell keeps a clamped log-odds of occupancy (1 byte) and the running
// mean of the laser hits that fell in it (3 bytes: sub-cell precision for
// scan matching, as in GMapping's point accumulators). A tile stores them as
// two planes, and the hit plane only once some cell of the tile has been
// hit: most tiles of a laser map are crossed by free-space rays alone (53-70
// % of the tiles of the Malaga, Edmonton and Acapulco maps), and those then
// take 1 KB instead of 4 KB, in every particle's copy.
//
// Thread safety: distinct OccupancyGrid objects may be read and written from
// different threads even when they share tiles (the copy-on-write test is
// synchronised through the shared_ptr reference count); one object must not
// be written from two threads at once.
#pragma once

#include <array>
#include <atomic>
#include <cstdint>
#include <memory>
#include <unordered_set>
#include <vector>

#include "hmt/common/pose2d.h"

namespace hmt::checkpoint {
struct Access;  // hmt/checkpoint/checkpoint.h
}  // namespace hmt::checkpoint

namespace hmt::grid {

constexpr int kTileBits = 5;
constexpr int kTileSize = 1 << kTileBits;  // cells per tile side
constexpr int kTileMask = kTileSize - 1;

// Log-odds in steps of 1/kLogOddsScale; one byte keeps the log-odds plane small,
// and the clamp (p_clamp) keeps values far from the type's limits.
using LogOdds = int8_t;

// The hit statistics of one cell.
struct HitMean {
  uint8_t hits = 0;  // laser hits seen here (saturating), for the mean
  int8_t hx = 0;     // mean hit offset from the cell centre, in
  int8_t hy = 0;     //   units of resolution / kHitScale
};

// A cell's whole state, as a value (tiles store it split in planes).
struct Cell {
  LogOdds logodds = 0;  // log-odds of occupancy, scaled by kLogOddsScale
  uint8_t hits = 0;
  int8_t hx = 0;
  int8_t hy = 0;
};
constexpr double kLogOddsScale = 20.0;
constexpr double kHitScale = 254.0;
// A probability's log-odds in steps of 1/kLogOddsScale, rounded: the
// thresholds that insertion, the matcher and TSBI compare cells against.
LogOdds scaled_logit(double p);

struct Tile {
  static constexpr int kCells = kTileSize * kTileSize;
  using HitPlane = std::array<HitMean, kCells>;

  std::array<LogOdds, kCells> logodds{};
  // Null until a cell of the tile is hit (then all zero but that cell's).
  std::unique_ptr<HitPlane> hit_means;

  Tile() = default;
  Tile(const Tile& o)
      : logodds(o.logodds),
        hit_means(o.hit_means ? std::make_unique<HitPlane>(*o.hit_means) : nullptr) {}
  Tile& operator=(const Tile&) = delete;

  HitMean hit(int i) const { return hit_means ? (*hit_means)[i] : HitMean{}; }
  HitMean& mutable_hit(int i) {
    if (!hit_means) hit_means = std::make_unique<HitPlane>();
    return (*hit_means)[i];
  }
  Cell cell(int i) const {
    const HitMean h = hit(i);
    return {logodds[i], h.hits, h.hx, h.hy};
  }
  // Sets the cell; a cell without hit statistics does not create the plane.
  void set(int i, const Cell& c) {
    logodds[i] = c.logodds;
    if (c.hits != 0 || c.hx != 0 || c.hy != 0 || hit_means) mutable_hit(i) = {c.hits, c.hx, c.hy};
  }
  // Memory the tile holds.
  size_t bytes() const { return sizeof(Tile) + (hit_means ? sizeof(HitPlane) : 0); }
};

// Integer cell coordinates; cell (i, j) covers [i*res, (i+1)*res) x [j*res, ...).
struct CellIndex {
  int x = 0;
  int y = 0;
};

class OccupancyGrid {
  // Checkpoints save and restore every member, bit for bit.
  friend struct hmt::checkpoint::Access;

 public:
  explicit OccupancyGrid(double resolution = 0.05);

  double resolution() const { return resolution_; }

  CellIndex cell_of(double x, double y) const {
    return {fast_floor(x * inv_resolution_), fast_floor(y * inv_resolution_)};
  }
  Point2D cell_center(CellIndex c) const {
    return {(c.x + 0.5) * resolution_, (c.y + 0.5) * resolution_};
  }

  // Index of a cell within its tile.
  static int index_in_tile(CellIndex c) {
    return ((c.y & kTileMask) << kTileBits) | (c.x & kTileMask);
  }
  // The tile at tile coordinates (cell >> kTileBits), or nullptr if never
  // written. Lets hot loops fetch a tile once for a block of cells.
  const Tile* tile(int tx, int ty) const { return tile_at(tx, ty); }
  // The tile holding cell c, or nullptr (unknown space).
  const Tile* tile_of(CellIndex c) const { return tile_at(c.x >> kTileBits, c.y >> kTileBits); }
  // Whether the cell's tile was ever written.
  bool known(CellIndex c) const { return tile_of(c) != nullptr; }
  // The cell's state (all zero in unknown space).
  Cell cell(CellIndex c) const {
    const Tile* t = tile_of(c);
    return t ? t->cell(index_in_tile(c)) : Cell{};
  }
  LogOdds logodds(CellIndex c) const {
    const Tile* t = tile_of(c);
    return t ? t->logodds[index_in_tile(c)] : 0;
  }
  // Mean position of the hits in an occupied cell (the centre if none).
  Point2D hit_mean(CellIndex c, int8_t hx, int8_t hy) const {
    const Point2D ctr = cell_center(c);
    const double k = resolution_ / kHitScale;
    return {ctr.x + hx * k, ctr.y + hy * k};
  }
  Point2D hit_mean(CellIndex c, const HitMean& h) const { return hit_mean(c, h.hx, h.hy); }
  Point2D hit_mean(CellIndex c, const Cell& cell) const { return hit_mean(c, cell.hx, cell.hy); }

  // Writers, cloning a shared tile or creating an unknown one.
  void set_cell(CellIndex c, const Cell& v) {
    mutable_tile(c.x >> kTileBits, c.y >> kTileBits).set(index_in_tile(c), v);
  }
  LogOdds& mutable_logodds(CellIndex c) {
    return mutable_tile(c.x >> kTileBits, c.y >> kTileBits).logodds[index_in_tile(c)];
  }
  // Writable tile at tile coordinates (cell >> kTileBits), same rules. Lets a
  // ray walk fetch its tile once per tile rather than once per cell.
  Tile& mutable_tile(int tx, int ty);

  // Bounds of the cells in allocated tiles: [min, max] inclusive. False if empty.
  bool bounds(CellIndex* min, CellIndex* max) const;

  // Whether this grid holds the very tiles of `o`, laid out alike: a copy
  // that neither grid has written since. Every cell then reads the same in
  // both (a shared tile is cloned before it is written).
  bool shares_every_tile_with(const OccupancyGrid& o) const;

  // Tiles this grid points to, and the bytes they would take if unshared.
  size_t tile_count() const;
  size_t tile_bytes() const;

  // Visits every distinct allocated tile once (for memory accounting across
  // many grids that share tiles).
  template <class F>
  void for_each_tile(F&& f) const {
    for (const auto& t : tiles_)
      if (t) f(t.get());
  }

  // Occupancy probability in [0,1], 0.5 for unknown.
  double probability(CellIndex c) const;

 private:
  static int fast_floor(double v) {
    const int i = static_cast<int>(v);
    return i - (v < i);
  }
  const Tile* tile_at(int tx, int ty) const {
    const int ix = tx - tx0_, iy = ty - ty0_;
    if (static_cast<unsigned>(ix) >= static_cast<unsigned>(ntx_) ||
        static_cast<unsigned>(iy) >= static_cast<unsigned>(nty_))
      return nullptr;
    return tiles_[static_cast<size_t>(iy) * ntx_ + ix].get();
  }
  void grow_to_include(int tx, int ty);

  double resolution_;
  double inv_resolution_;
  int tx0_ = 0, ty0_ = 0;  // tile coordinates of tiles_[0]
  int ntx_ = 0, nty_ = 0;  // table size in tiles
  std::vector<std::shared_ptr<Tile>> tiles_;
};

// The memory of the tiles of several grids that share tiles copy-on-write
// (particles, archived area maps), each distinct tile counted once.
class TileTally {
 public:
  void add(const OccupancyGrid& g) {
    g.for_each_tile([&](const Tile* t) {
      if (seen_.insert(t).second) bytes_ += t->bytes();
    });
  }
  size_t bytes() const { return bytes_; }

 private:
  std::unordered_set<const Tile*> seen_;
  size_t bytes_ = 0;
};

}  // namespace hmt::grid
