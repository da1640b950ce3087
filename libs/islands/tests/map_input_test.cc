#include "hmt/islands/map_input.h"

#include <gtest/gtest.h>

#include <fstream>

#include "hmt/common/error.h"
#include "hmt/topology/topology_file.h"
#include "hmt_test/scratch.h"

namespace hmt::islands {
namespace {

class MapInput : public ::testing::Test {
 protected:
  // The test's folder, removed if the test passes.
  void SetUp() override {
    dir_ = scratch::folder(std::string("islands_") +
                           ::testing::UnitTest::GetInstance()->current_test_info()->name())
               .string();
  }
  std::string write(const std::string& name, const std::string& text) {
    const std::string p = dir_ + "/" + name;
    std::ofstream(p, std::ios::binary) << text;
    return p;
  }
  // A 3 x 2 map: top row free, occupied, unknown (205); bottom row free,
  // free, uncertain (150: p = 0.41, observed but between the thresholds).
  void write_map() {
    const char pixels[] = {'\xfe', '\x00', '\xcd', '\xfe', '\xfe', '\x96'};
    write("m.pgm", std::string("P5\n# c\n3 2\n255\n") + std::string(pixels, sizeof pixels));
    write("m.yaml", "image: m.pgm\nresolution: 0.5\norigin: [-1.0, 2.0, 0.0]\nnegate: 0\n"
                    "occupied_thresh: 0.65\nfree_thresh: 0.196\n");
  }
  std::string dir_;
};

TEST_F(MapInput, ReadsAMapServerMapByItsYamlOrItsPgm) {
  write_map();
  for (const std::string name : {"m.yaml", "m.pgm"}) {
    SCOPED_TRACE(name);
    const LoadedMap m = load_map(dir_ + "/" + name);
    const OccupancyRaster r = m.raster();
    ASSERT_EQ(r.width, 3);
    ASSERT_EQ(r.height, 2);
    EXPECT_EQ(r.resolution, 0.5);
    EXPECT_EQ(r.origin_x, -1.0);
    EXPECT_EQ(r.origin_y, 2.0);
    EXPECT_NEAR(r.x_of(0), -0.75, 1e-12);
    // Image row 0 is the top: raster row 1.
    EXPECT_EQ(r.at(0, 1), CellState::kFree);
    EXPECT_EQ(r.at(1, 1), CellState::kOccupied);
    EXPECT_EQ(r.at(2, 1), CellState::kUnknown);
    EXPECT_EQ(r.at(0, 0), CellState::kFree);
    EXPECT_EQ(r.at(1, 0), CellState::kFree);
    EXPECT_EQ(r.at(2, 0), CellState::kUncertain);
    // With walls from p > 0.4, the uncertain cell (p = 0.41) is one.
    EXPECT_EQ(m.raster(0.4).at(2, 0), CellState::kOccupied);
  }
}

TEST_F(MapInput, BadMapsAreInputErrorsNamingTheFile) {
  EXPECT_THROW(load_map(dir_ + "/none.yaml"), InputError);
  const std::string junk = write("junk.bin", "not a map at all");
  try {
    load_map(junk);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("junk.bin"), std::string::npos);
  }
  write("lonely.pgm", "P5\n1 1\n255\n\x01");
  EXPECT_THROW(load_map(dir_ + "/lonely.pgm"), InputError);  // no .yaml
  write("m.pgm", "P5\n3 2\n255\n\x01\x02");                   // truncated
  write("m.yaml", "image: m.pgm\nresolution: 0.5\norigin: [0, 0, 0]\n");
  EXPECT_THROW(load_map(dir_ + "/m.yaml"), InputError);
  write_map();
  for (const std::string yaml :
       {"image: m.pgm\norigin: [0, 0, 0]\n", "image: m.pgm\nresolution: -1\norigin: [0, 0, 0]\n",
        "image: m.pgm\nresolution: abc\norigin: [0, 0, 0]\n",
        "image: m.pgm\nresolution: 0.1\norigin: [0, 0]\n",
        "image: m.pgm\nresolution: 0.1\norigin: [0, 0, 1.0]\n",
        "resolution: 0.1\norigin: [0, 0, 0]\n", "image: m.pgm\nresolution: 0.1\n",
        "image: m.pgm\nresolution: 0.1\norigin: [0, 0, 0]\nbogus: 1\n",
        "image: gone.pgm\nresolution: 0.1\norigin: [0, 0, 0]\n"}) {
    SCOPED_TRACE(yaml);
    write("bad.yaml", yaml);
    EXPECT_THROW(load_map(dir_ + "/bad.yaml"), InputError);
  }
}

TEST_F(MapInput, ReadsAnHmtMapFileAsItsGlobalMap) {
  grid::OccupancyGrid g(0.1);
  for (int i = -20; i < 20; ++i) g.set_cell({i, 10}, grid::Cell{100, 1, 0, 0});
  for (int i = -20; i < 20; ++i)
    for (int j = -5; j < 10; ++j) g.set_cell({i, j}, grid::Cell{-60, 0, 0, 0});
  topology::HmtMap map;
  map.add_area(0);
  map.archive_map(0, g);
  topology::Session s;
  s.steps = 1;
  topology::SessionHypothesis h;
  h.id = 0;
  h.map = map;
  topology::enter_area(h.topo, 0, 0);
  s.hypotheses.push_back(h);
  const std::string path = dir_ + "/hmt_map.bin";
  topology::save_session(path, s);
  const LoadedMap m = load_map(path);
  const OccupancyRaster r = m.raster();
  EXPECT_EQ(r.resolution, 0.1);
  // The wall row y = 10 cells (1.0 to 1.1 m) is occupied, below it free.
  const int i = static_cast<int>(std::floor((0.05 - r.origin_x) / 0.1));
  const int j = static_cast<int>(std::floor((1.05 - r.origin_y) / 0.1));
  EXPECT_EQ(r.at(i, j), CellState::kOccupied);
  EXPECT_EQ(r.at(i, j - 3), CellState::kFree);
  EXPECT_EQ(r.at(i, j + 3), CellState::kUnknown);
  EXPECT_NE(m.description.find("1 areas"), std::string::npos);
}

}  // namespace
}  // namespace hmt::islands
