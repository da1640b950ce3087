#include "hmt/grouping/images.h"

#include <gtest/gtest.h>

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

uint8_t grey_at(const cv::Mat& img, int r, int c) {
  return img.at<cv::Vec3b>(r, c)[0];
}

TEST(Images, WeightImageInGivenOrder) {
  const cv::Mat img = weight_image(interleaved(), {0, 1, 2, 3}, {}, 40);
  ASSERT_EQ(img.rows, 40);  // 10 pixels per cell
  ASSERT_EQ(img.type(), CV_8UC3);
  EXPECT_EQ(grey_at(img, 5, 5), 255);    // diagonal
  EXPECT_EQ(grey_at(img, 5, 25), 255);   // W(0, 2) = 1
  EXPECT_EQ(grey_at(img, 15, 35), 128);  // W(1, 3) = 0.5
  EXPECT_EQ(grey_at(img, 5, 15), 0);     // W(0, 1) = 0
}

TEST(Images, ReorderingGathersTheGroupsOnTheDiagonal) {
  const cv::Mat img = weight_image(interleaved(), {0, 2, 1, 3}, {2, 2}, 40);
  EXPECT_EQ(grey_at(img, 5, 15), 255);  // 0 and 2 now adjacent
  EXPECT_EQ(grey_at(img, 25, 35), 128);
  EXPECT_EQ(grey_at(img, 5, 25), 0);
  // Block outlines in the groups' colours: top-left corner of each block.
  EXPECT_EQ(img.at<cv::Vec3b>(0, 0), group_colour(0));
  EXPECT_EQ(img.at<cv::Vec3b>(20, 20), group_colour(1));
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
  const cv::Mat img = weight_image(W, order, {});
  ASSERT_EQ(img.rows, 2000);
  EXPECT_EQ(grey_at(img, 0, 1999), 179);  // 0.7 survives the pooling
}

TEST(Images, GroupsMapPaintsPointsInTheirGroupColour) {
  grid::MapImage m;
  m.image = cv::Mat(100, 100, CV_8UC1, cv::Scalar(205));
  m.resolution = 0.1;
  m.origin_x = -5.0;
  m.origin_y = -5.0;
  MapOverlay ov;
  ov.groups = 2;
  ov.pose = {Pose2D(-3, -3, 0), Pose2D(3, 3, 0)};
  ov.group = {0, 1};
  ov.points = {{Point2D{-4.0, 4.0}}, {Point2D{4.0, -4.0}}};
  const cv::Mat img = groups_map_image(m, ov);
  ASSERT_EQ(img.size(), m.image.size());
  // (-4, 4): column 10, row 99 - 90 = 9.
  EXPECT_EQ(img.at<cv::Vec3b>(9, 10), group_colour(0));
  EXPECT_EQ(img.at<cv::Vec3b>(89, 90), group_colour(1));
  EXPECT_EQ(img.at<cv::Vec3b>(50, 95), cv::Vec3b(205, 205, 205));
}

}  // namespace
}  // namespace hmt::grouping
