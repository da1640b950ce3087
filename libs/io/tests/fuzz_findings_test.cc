// Inputs the fuzz targets (fuzz/) found crashing a reader or making it
// return a wrong log, kept as they were found (testdata/fuzz/), each with
// the clear error it must now end in. The same files are in the fuzzers'
// seed corpora.
#include <gtest/gtest.h>

#include "hmt/io/carmen.h"
#include "hmt/io/log_reader.h"
#include "hmt/io/rawlog.h"
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

// A NaN aperture (a malaga scan's, flipped in its float) made every bearing
// NaN; an aperture of 7 rad is more than a turn; a NaN in the sensor pose's
// matrix made the sensor pose NaN. Found by fuzz_rawlog's check of the log's
// invariants on mutated seeds.
TEST(FuzzFindings, RawlogScanGeometryMustBeFinite) {
  const std::string nan_aperture = finding("rawlog-aperture-nan.rawlog");
  expect_input_error([&] { read_rawlog(nan_aperture); },
                     {nan_aperture, "scan 0 (entry 0) is unusable", "its aperture is nan rad"});
  const std::string wide = finding("rawlog-aperture-beyond-a-turn.rawlog");
  expect_input_error([&] { read_log(wide); },
                     {wide, "scan 0 (entry 0) is unusable", "its aperture is 7.0", "not in [0, 2 pi]"});
  const std::string pose = finding("rawlog-sensor-pose-nan.rawlog");
  expect_input_error([&] { read_rawlog(pose); },
                     {pose, "scan 0 (entry 0) is unusable", "its sensor pose is not finite"});
}

}  // namespace
}  // namespace hmt::io
