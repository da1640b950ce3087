// The scan matcher's view of the cells around a beam's end point: a
// square window of the grid read as rows, and the obstacles of a row as
// bits (scan_matcher.cc's inner loop; private to this library).
#pragma once

#include <cstdint>
#include <cstring>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "hmt/grid/occupancy_grid.h"

namespace hmt::metric_slam {

// Unknown space, and the hit plane of a tile without hits (all zero).
// Namespace-scope rather than function statics: no guard on every read.
inline const grid::Tile kUnknownTile{};
inline const grid::Tile::HitPlane kNoHits{};

// The square window of 2W+1 cells a side around `centre`, as rows of
// consecutive cells: inside the tile when the window lies in one tile (most
// windows), else in a small copy. Unknown space reads as all-zero log-odds
// without hits, as OccupancyGrid::cell() does.
template <int W>
class Window {
 public:
  static constexpr int kSide = 2 * W + 1;

  Window(const grid::OccupancyGrid& map, grid::CellIndex centre, bool with_hits) {
    using grid::kTileBits;
    using grid::kTileMask;
    const int x0 = centre.x - W, y0 = centre.y - W;
    const int tx = x0 >> kTileBits, ty = y0 >> kTileBits;
    if (tx == (x0 + 2 * W) >> kTileBits && ty == (y0 + 2 * W) >> kTileBits) {
      const grid::Tile* t = map.tile(tx, ty);
      const int i = ((y0 & kTileMask) << kTileBits) | (x0 & kTileMask);
      logodds_ = (t ? t->logodds.data() : kUnknownTile.logodds.data()) + i;
      if (with_hits) hits_ = (t && t->hit_means ? t->hit_means->data() : kNoHits.data()) + i;
      return;
    }
    stride_ = kSide;
    for (int r = 0; r < kSide; ++r)
      for (int c = 0; c < kSide; ++c) {
        const grid::CellIndex cq{x0 + c, y0 + r};
        const grid::Tile* t = map.tile_of(cq);
        const int i = grid::OccupancyGrid::index_in_tile(cq);
        const int j = r * kSide + c;
        logodds_copy_[j] = t ? t->logodds[i] : 0;
        if (with_hits) hits_copy_[j] = t ? t->hit(i) : grid::HitMean{};
      }
    logodds_ = logodds_copy_;
    hits_ = hits_copy_;
  }
  Window(const Window&) = delete;
  Window& operator=(const Window&) = delete;

  const grid::LogOdds* logodds(int r) const { return logodds_ + r * stride_; }
  const grid::HitMean& hit(int r, int c) const { return hits_[r * stride_ + c]; }

 private:
  const grid::LogOdds* logodds_ = nullptr;
  const grid::HitMean* hits_ = nullptr;
  int stride_ = grid::kTileSize;  // cells from one row to the next
  grid::LogOdds logodds_copy_[kSide * kSide];
  grid::HitMean hits_copy_[kSide * kSide];
};

#if defined(__SSE2__)
// A window row of N (odd, <= 7) bytes into the low lanes of a register, as
// 4-, 2- and 1-byte loads straight into registers: one 8-byte copy through
// memory stalls on store forwarding, and reading past the row's N bytes
// could leave the tile.
template <int N>
__m128i load_bytes(const grid::LogOdds* p) {
  static_assert(N % 2 == 1 && N <= 7);
  uint64_t v = 0;
  int at = 0;
  if constexpr (N >= 4) {
    uint32_t w;
    std::memcpy(&w, p, 4);
    v = w;
    at = 4;
  }
  if constexpr (N % 4 == 3) {
    uint16_t w;
    std::memcpy(&w, p + at, 2);
    v |= static_cast<uint64_t>(w) << (8 * at);
    at += 2;
  }
  v |= static_cast<uint64_t>(static_cast<uint8_t>(p[at])) << (8 * at);
  return _mm_cvtsi64_si128(static_cast<long long>(v));
}
#endif

// Bit c set where cell c of a window row is an obstacle: occupied (at or
// above `threshold`) with its free-space probe cell below it. Computed
// without branches: whether a cell is occupied follows no pattern a CPU
// could predict, and a branch per cell cost more than the cells' arithmetic.
template <int kSide>
uint32_t obstacle_bits(const grid::LogOdds* hit, const grid::LogOdds* probe,
                       grid::LogOdds threshold) {
#if defined(__SSE2__)
  if constexpr (kSide <= 7) {
    const __m128i t = _mm_set1_epi8(threshold);
    const __m128i below_h = _mm_cmpgt_epi8(t, load_bytes<kSide>(hit));
    const __m128i below_f = _mm_cmpgt_epi8(t, load_bytes<kSide>(probe));
    const int m = _mm_movemask_epi8(_mm_andnot_si128(below_h, below_f));
    return static_cast<uint32_t>(m) & ((1u << kSide) - 1);
  }
#endif
  uint32_t m = 0;
  for (int c = 0; c < kSide; ++c)
    m |= static_cast<uint32_t>((hit[c] >= threshold) & (probe[c] < threshold)) << c;
  return m;
}

// Calls g(mx, my) with the hit mean of every obstacle in the window of
// radius W around cell `hit` (probed through the same offsets around cell
// `probe`), row by row, left to right.
template <int W, class G>
void for_each_obstacle(const grid::OccupancyGrid& map, grid::CellIndex hit,
                       grid::CellIndex probe, grid::LogOdds threshold, G&& g) {
  constexpr int kSide = 2 * W + 1;
  const Window<W> hw(map, hit, true), pw(map, probe, false);
  const double res = map.resolution(), k = res / grid::kHitScale;
  auto visit = [&](int r, int col) {
    const grid::HitMean h = hw.hit(r, col);
    g((hit.x - W + col + 0.5) * res + h.hx * k,  // as OccupancyGrid::hit_mean()
      (hit.y - W + r + 0.5) * res + h.hy * k);
  };
  if constexpr (kSide * kSide <= 64) {
    // One word for the whole window: a single loop over its obstacles.
    uint64_t bits = 0;
#pragma GCC unroll 8
    for (int r = 0; r < kSide; ++r)
      bits |= static_cast<uint64_t>(obstacle_bits<kSide>(hw.logodds(r), pw.logodds(r), threshold))
              << (r * kSide);
    for (; bits != 0; bits &= bits - 1) {
      const int b = __builtin_ctzll(bits);
      visit(b / kSide, b % kSide);
    }
  } else {
    for (int r = 0; r < kSide; ++r)
      for (uint32_t bits = obstacle_bits<kSide>(hw.logodds(r), pw.logodds(r), threshold);
           bits != 0; bits &= bits - 1)
        visit(r, __builtin_ctz(bits));
  }
}

}  // namespace hmt::metric_slam
