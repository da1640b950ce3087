#include "hmt/grid/image.h"

#include <gtest/gtest.h>

#include <stdexcept>

namespace hmt::grid {
namespace {

TEST(Image, HoldsRowsOfInterleavedChannels) {
  Image g(4, 3, 1, 7);
  EXPECT_EQ(g.width(), 4);
  EXPECT_EQ(g.height(), 3);
  EXPECT_EQ(g.pixels().size(), 12u);
  g.at(3, 2) = 9;
  EXPECT_EQ(g.row(2)[3], 9);
  const Image c = grey_to_bgr(g);
  EXPECT_EQ(c.channels(), 3);
  EXPECT_EQ(c.bgr(3, 2), Bgr::grey(9));
  EXPECT_EQ(c.bgr(0, 0), Bgr::grey(7));
  EXPECT_EQ(c.row(1) - c.row(0), 12);
  EXPECT_TRUE(Image().empty());
  EXPECT_TRUE(Image(0, 5, 3).empty());
  EXPECT_THROW(Image(2, 2, 2), std::invalid_argument);
  EXPECT_THROW(Image(-1, 2, 1), std::invalid_argument);
  EXPECT_THROW(grey_to_bgr(c), std::invalid_argument);
}

}  // namespace
}  // namespace hmt::grid
