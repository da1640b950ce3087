#include "hmt/grouping/images.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

namespace hmt::grouping {
namespace {

// Nodes 0 and 2 overlap strongly, 1 and 3 too; nothing else.
area::WeightMatrix interleaved() {
  std::vector<Eigen::Triplet<double>> t = {
      {0, 2, 1.0}, {2, 0, 1.0}, {1, 3, 0.5}, {3, 1, 0.5}};
  area::WeightMatrix W(4, 4);
  W.setFromTriplets(t.begin(), t.end());
  return W;
}

uint8_t grey_at(const grid::Image& img, int r, int c) { return img.at(c, r); }

TEST(Images, WeightImageInGivenOrder) {
  const grid::Image img = weight_image(interleaved(), {0, 1, 2, 3}, {}, 40);
  ASSERT_EQ(img.height(), 40);  // 10 pixels per cell
  ASSERT_EQ(img.width(), 40);
  ASSERT_EQ(img.channels(), 3);
  EXPECT_EQ(grey_at(img, 5, 5), 255);    // diagonal
  EXPECT_EQ(grey_at(img, 5, 25), 255);   // W(0, 2) = 1
  EXPECT_EQ(grey_at(img, 15, 35), 128);  // W(1, 3) = 0.5
  EXPECT_EQ(grey_at(img, 5, 15), 0);     // W(0, 1) = 0
}

TEST(Images, ReorderingGathersTheGroupsOnTheDiagonal) {
  const grid::Image img = weight_image(interleaved(), {0, 2, 1, 3}, {2, 2}, 40);
  EXPECT_EQ(grey_at(img, 5, 15), 255);  // 0 and 2 now adjacent
  EXPECT_EQ(grey_at(img, 25, 35), 128);
  EXPECT_EQ(grey_at(img, 5, 25), 0);
  // Block outlines in the groups' colours: top-left corner of each block.
  EXPECT_EQ(img.bgr(0, 0), group_colour(0));
  EXPECT_EQ(img.bgr(19, 0), group_colour(0));
  EXPECT_EQ(img.bgr(0, 19), group_colour(0));
  EXPECT_EQ(img.bgr(20, 20), group_colour(1));
  EXPECT_EQ(img.bgr(39, 39), group_colour(1));
  EXPECT_EQ(grey_at(img, 10, 10), 255);  // inside the outline
  EXPECT_THROW(weight_image(interleaved(), {0, 0, 1, 3}, {}), std::invalid_argument);
  EXPECT_THROW(weight_image(interleaved(), {0, 1, 2, 3}, {3, 2}), std::invalid_argument);
}

TEST(Images, LargeMatricesArePooledByTheirMaximum) {
  const int n = 4001;
  std::vector<Eigen::Triplet<double>> t = {{0, 4000, 0.7}, {4000, 0, 0.7}};
  area::WeightMatrix W(n, n);
  W.setFromTriplets(t.begin(), t.end());
  std::vector<int> order(n);
  for (int i = 0; i < n; ++i) order[i] = i;
  const grid::Image img = weight_image(W, order, {});
  ASSERT_EQ(img.height(), 2000);
  EXPECT_EQ(grey_at(img, 0, 1999), 179);  // 0.7 survives the pooling
}

TEST(Images, GroupsMapPaintsPointsInTheirGroupColour) {
  grid::MapImage m;
  m.image = grid::Image(100, 100, 1, 205);
  m.resolution = 0.1;
  m.origin_x = -5.0;
  m.origin_y = -5.0;
  MapOverlay ov;
  ov.groups = 2;
  ov.pose = {Pose2D(-3, -3, 0), Pose2D(3, 3, 0)};
  ov.group = {0, 1};
  ov.points = {{Point2D{-4.0, 4.0}}, {Point2D{4.0, -4.0}}};
  const grid::Image img = groups_map_image(m, ov);
  ASSERT_EQ(img.width(), m.image.width());
  ASSERT_EQ(img.height(), m.image.height());
  // (-4, 4): column 10, row 99 - 90 = 9.
  EXPECT_EQ(img.bgr(10, 9), group_colour(0));
  EXPECT_EQ(img.bgr(90, 89), group_colour(1));
  EXPECT_EQ(img.bgr(95, 50), grid::Bgr::grey(205));
  // The keyframes: dots in their group's colour, the route between them.
  EXPECT_EQ(img.bgr(20, 79), group_colour(0));  // (-3, -3)
  EXPECT_EQ(img.bgr(80, 19), group_colour(1));  // (3, 3)
  EXPECT_EQ(img.bgr(50, 49), grid::Bgr::grey(90));
  // Each group's id, in its colour, up and right of its keyframe.
  for (int g = 0; g < 2; ++g) {
    const int x0 = g == 0 ? 20 : 80, y0 = g == 0 ? 79 : 19;
    int n = 0;
    for (int y = std::max(0, y0 - 14); y < y0 - 2; ++y)  // clear of the dot
      for (int x = x0 + 3; x < std::min(100, x0 + 14); ++x)
        n += img.bgr(x, y) == group_colour(g);
    EXPECT_GE(n, 7) << g;
  }
}

}  // namespace
}  // namespace hmt::grouping
