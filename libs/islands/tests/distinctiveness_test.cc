#include "hmt/islands/distinctiveness.h"

#include <gtest/gtest.h>

#include <cmath>

#include "test_maps.h"

namespace hmt::islands {
namespace {

using test::Segment;

constexpr double kRes = 0.1;

// The defaults but for the normals' radius: 5 cells, as the default 0.25 m
// is at the 5 cm cells of the maps a run draws.
IslandsOptions options() {
  IslandsOptions o;
  o.normal_radius = 0.5;
  o.threads = 2;
  return o;
}

float r_at(const OccupancyRaster& m, const DistinctivenessMap& d, double x, double y) {
  const int i = static_cast<int>(std::floor(x / m.resolution));
  const int j = static_cast<int>(std::floor(y / m.resolution));
  return d.r[m.index(i, j)];
}

// A corridor 2 m wide and 30 m long along x, open at both ends.
OccupancyRaster corridor() {
  return test::walls(32, 6, kRes, {{1, 2, 31, 2}, {1, 4, 31, 4}});
}

// An L of corridors 2 m wide: along x from x = 1 to 18, then up along y;
// its outer corner at (18, 2), the bend's centre at (17, 3). Placed in a
// 40 m square (centre (20, 20)) so that it can be turned about the centre.
std::vector<Segment> l_corridor() {
  return {{5, 12, 22, 12}, {22, 12, 22, 30}, {5, 14, 20, 14}, {20, 14, 20, 30}};
}
// Its inside (the rest is unknown), walls included.
std::vector<Segment> l_inside() { return {{5, 11.9, 22.1, 14}, {20, 11.9, 22.1, 30}}; }
OccupancyRaster l_map(double angle = 0.0) {
  return test::walls(40, 40, kRes, l_corridor(), angle, l_inside());
}

// Two corridors 2 m wide crossing at (10, 10).
OccupancyRaster crossing() {
  return test::walls(20, 20, kRes,
                     {{1, 9, 9, 9}, {11, 9, 19, 9}, {1, 11, 9, 11}, {11, 11, 19, 11},
                      {9, 1, 9, 9}, {11, 1, 11, 9}, {9, 11, 9, 19}, {11, 11, 11, 19}},
                     0.0, {{1, 8.9, 19, 11.1}, {8.9, 1, 11.1, 19}});
}

TEST(Sigmoid, MatchesEquation11) {
  // C^m / (c^m + C^m) by hand.
  EXPECT_DOUBLE_EQ(sigmoid(0.5, 0.5, 4), 0.5);
  EXPECT_NEAR(sigmoid(1.0, 0.5, 4), 1.0 / (0.0625 + 1.0), 1e-12);  // 16 / 17
  EXPECT_NEAR(sigmoid(0.25, 0.5, 2), 0.0625 / (0.25 + 0.0625), 1e-12);  // 0.2
  EXPECT_NEAR(sigmoid(2.0, 1.0, 3), 8.0 / 9.0, 1e-12);
  EXPECT_EQ(sigmoid(0.0, 0.5, 4), 0.0);
  EXPECT_LT(sigmoid(0.1, 0.5, 4), sigmoid(0.2, 0.5, 4));
  EXPECT_NEAR(sigmoid(1e6, 0.5, 4), 1.0, 1e-12);
}

TEST(Quality, MatchesEquation12) {
  EXPECT_DOUBLE_EQ(quality(0.8, 0.2), 0.25);  // C_par > C_perp: C_perp / C_par
  EXPECT_DOUBLE_EQ(quality(0.2, 0.8), 0.25);  // otherwise C_par / C_perp
  EXPECT_DOUBLE_EQ(quality(0.6, 0.6), 1.0);
  EXPECT_DOUBLE_EQ(quality(0.7, 0.0), 0.0);
  EXPECT_DOUBLE_EQ(quality(0.0, 0.0), 0.0);
}

TEST(Constraints, ReferenceIsTheLargestSurface) {
  const double pi = std::acos(-1.0);
  // Along x (3), along y (0.5), at 30 degrees (2): the x surface is the
  // largest, so C_par = 3 + 2 cos 30, C_perp = 0.5 + 2 sin 30 (Eq. 9-10).
  const Constraints c = constraints({{1, 0, 3.0}, {0, 1, 0.5}, {std::cos(pi / 6), std::sin(pi / 6), 2.0}},
                                    15 * pi / 180);
  EXPECT_NEAR(std::abs(c.ref_x), 1.0, 1e-6);
  EXPECT_NEAR(c.parallel, 3.0 + 2.0 * std::cos(pi / 6), 1e-5);
  EXPECT_NEAR(c.perp, 0.5 + 2.0 * std::sin(pi / 6), 1e-5);
  // Two influences 4 degrees apart are one surface (window 15): together
  // (1.5) they outweigh the single one (1.2) across them, and the reference
  // lies between them.
  const double a = 88 * pi / 180, b = 92 * pi / 180;
  const Constraints d = constraints(
      {{std::cos(a), std::sin(a), 0.75}, {std::cos(b), std::sin(b), 0.75}, {1, 0, 1.2}},
      15 * pi / 180);
  EXPECT_NEAR(std::abs(d.ref_y), 1.0, 1e-6);
  EXPECT_NEAR(d.parallel, 1.5 * std::cos(2 * pi / 180), 1e-5);
  EXPECT_NEAR(d.perp, 1.2 + 1.5 * std::sin(2 * pi / 180), 1e-5);
  // A sign flip is the same axis.
  const Constraints e = constraints({{-1, 0, 1.0}, {0, -1, 1.0}}, 15 * pi / 180);
  EXPECT_NEAR(e.parallel, 1.0, 1e-6);
  EXPECT_NEAR(e.perp, 1.0, 1e-6);
  EXPECT_EQ(constraints({}, 0.2).parallel, 0.0);
}

TEST(Distinctiveness, CorridorIsLowAlongItsLength) {
  const OccupancyRaster m = corridor();
  const IslandsOptions o = options();
  for (double x : {8.0, 16.0, 24.0}) {
    SCOPED_TRACE(x);
    const CellTerms t = cell_terms(m, static_cast<int>(x / kRes), 30, o);
    EXPECT_GT(t.c_parallel, 1.0);  // both walls constrain across the corridor
    EXPECT_LT(t.c_perp, 0.05 * t.c_parallel);
    EXPECT_LT(t.q, 0.05);
    EXPECT_LT(t.f, 0.05);
  }
  const DistinctivenessMap d = distinctiveness(m, o);
  EXPECT_LT(r_at(m, d, 16.05, 3.05), 0.05);
  EXPECT_TRUE(std::isnan(r_at(m, d, 16.05, 2.05)));  // a wall has no R
}

// Rays pass through uncertain cells (observed, neither free nor occupied)
// and end at unknown ones.
TEST(Distinctiveness, RaysCrossUncertainCellsAndStopAtUnknownOnes) {
  const IslandsOptions o = options();
  OccupancyRaster m = crossing();
  const CellTerms clear = cell_terms(m, 100, 100, o);
  for (int j = 0; j < m.height; ++j)
    for (int i = 92; i <= 93; ++i)
      if (m.at(i, j) == CellState::kFree) m.at(i, j) = CellState::kUncertain;
  const CellTerms through = cell_terms(m, 100, 100, o);
  EXPECT_FLOAT_EQ(through.c_parallel + through.c_perp, clear.c_parallel + clear.c_perp);
  for (int j = 0; j < m.height; ++j)
    for (int i = 92; i <= 93; ++i)
      if (m.at(i, j) == CellState::kUncertain) m.at(i, j) = CellState::kUnknown;
  const CellTerms blocked = cell_terms(m, 100, 100, o);
  EXPECT_LT(blocked.c_parallel + blocked.c_perp, clear.c_parallel + clear.c_perp - 0.05);
}

TEST(Distinctiveness, CornerAndCrossingAreHigh) {
  const IslandsOptions o = options();
  const OccupancyRaster l = l_map();
  const DistinctivenessMap dl = distinctiveness(l, o);
  const float corner = r_at(l, dl, 21.05, 13.05);
  const float straight = r_at(l, dl, 12.05, 13.05);
  EXPECT_GT(corner, 0.5);
  EXPECT_LT(straight, 0.1);
  const CellTerms t = cell_terms(l, 210, 130, o);
  EXPECT_GT(t.q, 0.5);

  const OccupancyRaster x = crossing();
  const DistinctivenessMap dx = distinctiveness(x, o);
  EXPECT_GT(r_at(x, dx, 10.05, 10.05), 0.5);
  EXPECT_GT(r_at(x, dx, 10.05, 10.05), 5 * r_at(x, dx, 10.05, 4.05));
}

TEST(Distinctiveness, TurningTheGrid90DegreesTurnsR) {
  const IslandsOptions o = options();
  const OccupancyRaster m = l_map();
  const OccupancyRaster t = test::rotate90(m);
  const DistinctivenessMap a = distinctiveness(m, o), b = distinctiveness(t, o);
  double worst = 0.0, total = 0.0;
  size_t n = 0;
  for (int j = 0; j < m.height; ++j)
    for (int i = 0; i < m.width; ++i) {
      const float ra = a.r[m.index(i, j)], rb = b.r[t.index(m.height - 1 - j, i)];
      ASSERT_EQ(std::isnan(ra), std::isnan(rb));
      if (std::isnan(ra)) continue;
      worst = std::max(worst, static_cast<double>(std::abs(ra - rb)));
      total += std::abs(ra - rb);
      ++n;
    }
  EXPECT_LT(total / n, 1e-3);
  EXPECT_LT(worst, 0.05);
}

TEST(Distinctiveness, TurningTheWallsByAnyAngleKeepsR) {
  const IslandsOptions o = options();
  const double angle = 0.5;  // about 28.6 degrees
  const OccupancyRaster a = l_map();
  const OccupancyRaster b = l_map(angle);
  const DistinctivenessMap da = distinctiveness(a, o), db = distinctiveness(b, o);
  const double c = std::cos(angle), s = std::sin(angle);
  for (const auto& p : {std::pair<double, double>{21.0, 13.0}, {21.0, 20.0}, {12.0, 13.0},
                        {20.5, 12.5}}) {
    SCOPED_TRACE(::testing::Message() << p.first << ", " << p.second);
    const double x = 20 + c * (p.first - 20) - s * (p.second - 20);
    const double y = 20 + s * (p.first - 20) + c * (p.second - 20);
    EXPECT_NEAR(r_at(a, da, p.first, p.second), r_at(b, db, x, y), 0.08);
  }
}

TEST(Distinctiveness, ThreadsDoNotChangeTheResult) {
  IslandsOptions o = options();
  const OccupancyRaster m = crossing();
  o.threads = 1;
  const DistinctivenessMap a = distinctiveness(m, o);
  o.threads = 3;
  const DistinctivenessMap b = distinctiveness(m, o);
  ASSERT_EQ(a.r.size(), b.r.size());
  for (size_t k = 0; k < a.r.size(); ++k) {
    if (std::isnan(a.r[k])) continue;
    ASSERT_EQ(a.r[k], b.r[k]) << k;
  }
}

TEST(Distinctiveness, EpsilonAveragesOverTheSquare) {
  IslandsOptions o = options();
  const OccupancyRaster m = crossing();
  o.epsilon = 0.0;
  const DistinctivenessMap point = distinctiveness(m, o);
  // With epsilon 0, R is the cell's own F (1 + Q) / 2 (Eq. 4 over a point).
  for (size_t k = 0; k < point.evaluated.size(); k += 97)
    EXPECT_NEAR(point.r[point.evaluated[k]], point.terms[k].term(), 1e-6);
  // With epsilon 0.3 m (3 cells), the mean of the 7 x 7 free cells around.
  o.epsilon = 0.3;
  const DistinctivenessMap avg = distinctiveness(m, o);
  const int i = 100, j = 60;
  double total = 0.0;
  int n = 0;
  for (int y = j - 3; y <= j + 3; ++y)
    for (int x = i - 3; x <= i + 3; ++x)
      if (!std::isnan(point.r[m.index(x, y)])) {
        total += point.r[m.index(x, y)];
        ++n;
      }
  EXPECT_NEAR(avg.r[m.index(i, j)], total / n, 1e-5);
}

TEST(Distinctiveness, StrideEvaluatesALatticeAndFillsEveryFreeCell) {
  IslandsOptions o = options();
  o.stride = 2;
  o.epsilon = 0.0;
  const OccupancyRaster m = crossing();
  const DistinctivenessMap d = distinctiveness(m, o);
  size_t free_cells = 0, with_r = 0;
  for (size_t k = 0; k < m.cells.size(); ++k)
    if (m.cells[k] == CellState::kFree) {
      ++free_cells;
      with_r += !std::isnan(d.r[k]);
    }
  EXPECT_LT(d.evaluated.size(), free_cells / 3);
  EXPECT_GT(with_r, free_cells * 95 / 100);
}

TEST(Distinctiveness, NarrowFieldOfViewTakesTheBestHeading) {
  IslandsOptions o = options();
  const OccupancyRaster m = l_map();
  o.field_of_view = 180;
  o.headings = 8;
  const CellTerms narrow = cell_terms(m, 210, 130, o);
  o.headings = 1;  // facing +x only: the bend's corner is half behind
  const CellTerms one = cell_terms(m, 210, 130, o);
  EXPECT_GE(narrow.term(), one.term());
  EXPECT_GT(narrow.term(), 0.3);
}

}  // namespace
}  // namespace hmt::islands
