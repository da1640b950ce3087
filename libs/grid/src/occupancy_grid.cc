#include "hmt/grid/occupancy_grid.h"

#include <algorithm>
#include <cmath>

#include "hmt/common/sole_owner.h"

namespace hmt::grid {

LogOdds scaled_logit(double p) {
  return static_cast<LogOdds>(std::lround(std::log(p / (1.0 - p)) * kLogOddsScale));
}

OccupancyGrid::OccupancyGrid(double resolution)
    : resolution_(resolution), inv_resolution_(1.0 / resolution) {}

void OccupancyGrid::grow_to_include(int tx, int ty) {
  if (ntx_ == 0) {
    // First tile: start with a small table centred on it.
    tx0_ = tx - 4;
    ty0_ = ty - 4;
    ntx_ = nty_ = 8;
    tiles_.assign(static_cast<size_t>(ntx_) * nty_, nullptr);
    return;
  }
  // Grow by at least half the current size on the side needed, so that a
  // robot moving steadily causes O(log) re-tablings, not one per tile.
  int nx0 = tx0_, ny0 = ty0_, nx1 = tx0_ + ntx_, ny1 = ty0_ + nty_;
  if (tx < nx0) nx0 = std::min(tx, tx0_ - ntx_ / 2);
  if (tx >= nx1) nx1 = std::max(tx + 1, nx1 + ntx_ / 2);
  if (ty < ny0) ny0 = std::min(ty, ty0_ - nty_ / 2);
  if (ty >= ny1) ny1 = std::max(ty + 1, ny1 + nty_ / 2);
  std::vector<std::shared_ptr<Tile>> t(static_cast<size_t>(nx1 - nx0) * (ny1 - ny0));
  for (int y = 0; y < nty_; ++y)
    for (int x = 0; x < ntx_; ++x)
      t[static_cast<size_t>(y + ty0_ - ny0) * (nx1 - nx0) + (x + tx0_ - nx0)] =
          std::move(tiles_[static_cast<size_t>(y) * ntx_ + x]);
  tiles_ = std::move(t);
  tx0_ = nx0;
  ty0_ = ny0;
  ntx_ = nx1 - nx0;
  nty_ = ny1 - ny0;
}

bool OccupancyGrid::shares_every_tile_with(const OccupancyGrid& o) const {
  if (resolution_ != o.resolution_ || tx0_ != o.tx0_ || ty0_ != o.ty0_ || ntx_ != o.ntx_ ||
      nty_ != o.nty_)
    return false;
  for (size_t i = 0; i < tiles_.size(); ++i)
    if (tiles_[i] != o.tiles_[i]) return false;
  return true;
}

Tile& OccupancyGrid::mutable_tile(int tx, int ty) {
  int ix = tx - tx0_, iy = ty - ty0_;
  if (ix < 0 || iy < 0 || ix >= ntx_ || iy >= nty_) {
    grow_to_include(tx, ty);
    ix = tx - tx0_;
    iy = ty - ty0_;
  }
  auto& slot = tiles_[static_cast<size_t>(iy) * ntx_ + ix];
  if (!slot) {
    slot = std::make_shared<Tile>();
  } else if (slot.use_count() > 1) {
    slot = std::make_shared<Tile>(*slot);
  } else {
    // Sole owner: another grid that shared this tile released it after
    // copying; pair with that release before writing in place.
    acquire_sole_ownership(slot);
  }
  return *slot;
}


bool OccupancyGrid::bounds(CellIndex* min, CellIndex* max) const {
  bool any = false;
  for (int y = 0; y < nty_; ++y)
    for (int x = 0; x < ntx_; ++x) {
      if (!tiles_[static_cast<size_t>(y) * ntx_ + x]) continue;
      const int cx = (x + tx0_) * kTileSize, cy = (y + ty0_) * kTileSize;
      if (!any) {
        *min = {cx, cy};
        *max = {cx + kTileSize - 1, cy + kTileSize - 1};
        any = true;
      } else {
        min->x = std::min(min->x, cx);
        min->y = std::min(min->y, cy);
        max->x = std::max(max->x, cx + kTileSize - 1);
        max->y = std::max(max->y, cy + kTileSize - 1);
      }
    }
  return any;
}

size_t OccupancyGrid::tile_count() const {
  size_t n = 0;
  for (const auto& t : tiles_) n += (t != nullptr);
  return n;
}

size_t OccupancyGrid::tile_bytes() const {
  size_t n = 0;
  for (const auto& t : tiles_)
    if (t) n += t->bytes();
  return n;
}

double OccupancyGrid::probability(CellIndex c) const {
  const double l = logodds(c) / kLogOddsScale;
  return 1.0 / (1.0 + std::exp(-l));
}

}  // namespace hmt::grid
