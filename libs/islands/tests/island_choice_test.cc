#include "hmt/islands/island_choice.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace hmt::islands {
namespace {

// A 40 x 20 free raster at 0.1 m with R given per cell.
struct Field {
  OccupancyRaster map{40, 20, 0.1, CellState::kFree};
  DistinctivenessMap d;
  Field() {
    d.width = 40;
    d.height = 20;
    d.r.assign(map.cells.size(), 0.1f);
  }
  void set(int i, int j, float r) { d.r[map.index(i, j)] = r; }
};

TEST(ChooseIslands, LocalMaximaAboveTheThresholdFarEnoughApart) {
  Field f;
  f.set(5, 5, 0.9f);
  f.set(6, 5, 0.85f);   // beside the first: suppressed
  f.set(30, 10, 0.7f);  // 2.6 m away: an island
  f.set(20, 10, 0.4f);  // below the threshold
  f.d.r[f.map.index(0, 0)] = std::numeric_limits<float>::quiet_NaN();
  const std::vector<Island> is = choose_islands(f.map, f.d, 0.5, 1.0);
  ASSERT_EQ(is.size(), 2u);
  EXPECT_EQ(is[0].id, 1);
  EXPECT_EQ(is[0].i, 5);
  EXPECT_EQ(is[0].j, 5);
  EXPECT_NEAR(is[0].x, 0.55, 1e-9);
  EXPECT_NEAR(is[0].r, 0.9, 1e-6);
  EXPECT_EQ(is[1].i, 30);
  EXPECT_EQ(is[1].j, 10);
  // A larger separation drops the second; a zero one keeps the neighbour.
  EXPECT_EQ(choose_islands(f.map, f.d, 0.5, 3.0).size(), 1u);
  EXPECT_EQ(choose_islands(f.map, f.d, 0.5, 0.0).size(), 3u);
  EXPECT_TRUE(choose_islands(f.map, f.d, 0.95, 1.0).empty());
}

TEST(ChooseIslands, EqualValuesAreTakenInRasterOrder) {
  Field f;
  f.set(10, 3, 0.8f);
  f.set(2, 7, 0.8f);
  const std::vector<Island> is = choose_islands(f.map, f.d, 0.5, 100.0);
  ASSERT_EQ(is.size(), 1u);
  EXPECT_EQ(is[0].i, 10);  // row 3 comes before row 7
}

}  // namespace
}  // namespace hmt::islands
