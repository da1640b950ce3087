// Inputs the fuzz targets (fuzz/) found crashing a reader or making it
// return a wrong log, kept as they were found (testdata/fuzz/), each with
// the clear error it must now end in. The same files are in the fuzzers'
// seed corpora.
#include <gtest/gtest.h>

#include "hmt/io/carmen.h"
#include "hmt/io/log_reader.h"
#include "io_test_util.h"

namespace hmt::io {
namespace {

using namespace testing_util;

std::string finding(const std::string& name) {
  return repo_path("libs/io/tests/testdata/fuzz/" + name);
}

// A reading of 1e52 m became +inf as a float, and so did the log's max_range.
TEST(FuzzFindings, CarmenRangeBeyondAFloat) {
  const std::string p = finding("carmen-range-overflows-float.log");
  expect_input_error([&] { read_carmen(p); },
                     {p, "line 3", "range 146 is 1000000", "beyond what a float holds"});
  expect_input_error([&] { read_log(p); }, {p, "beyond what a float holds"});
}

// Hand-made neighbours of that finding: the ROBOTLASER1 angles, which are
// floats too, and a field of view that no 2D scanner has.
TEST(FuzzFindings, CarmenRobotLaserAnglesBeyondOneTurn) {
  const std::string dir = scratch_dir();
  // 3 beams, no remissions, laser and robot poses, velocities and safety
  // margins, timestamps.
  const std::string tail = " 1 2 3 0  0 0 0  0 0 0  0 0 0 0 0  1 h 1\n";
  write_bytes(dir + "/start.log", "ROBOTLASER1 0 1e39 3 1 20 0.01 0 3" + tail);
  expect_input_error([&] { read_carmen(dir + "/start.log"); },
                     {"line 1", "start_angle 1e39 is not an angle"});
  write_bytes(dir + "/res.log", "ROBOTLASER1 0 -1.5 3 4 20 0.01 0 3" + tail);
  expect_input_error([&] { read_carmen(dir + "/res.log"); },
                     {"line 1", "angular_resolution 4", "more than a full turn"});
}

}  // namespace
}  // namespace hmt::io
