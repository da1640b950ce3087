// Every class version MRPT 2.5.8 reads, in files made by hand (the installed
// MRPT only writes the newest versions): MRPT's deserializers and the
// native reader must give the same log, bit for bit, and the native reader
// must not need MRPT for any of them.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <string>

#include "archive_bytes.h"
#include "hmt/io/rawlog.h"
#include "io_test_util.h"
#include "mrpt_fallback.h"

namespace hmt::io {
namespace {

using namespace testing_util;

// Reads `bytes` as a rawlog both ways and compares (see
// expect_identical_logs() for `time_tolerance`).
void expect_same_reading(const Bytes& bytes, double time_tolerance = 0.0) {
  const std::string p = scratch_dir() + "/made.rawlog";
  write_bytes(p, bytes.bytes());
  const size_t fallbacks = detail::mrpt_fallback_reads();
  hmt::Log native;
  try {
    native = read_rawlog(p);
  } catch (const std::exception& e) {
    FAIL() << "native reader: " << e.what();
  }
  EXPECT_EQ(detail::mrpt_fallback_reads(), fallbacks) << "read through MRPT";
  hmt::Log mrpt;
  try {
    mrpt = detail::read_rawlog_with_mrpt(p, false, "the test's objects");
  } catch (const std::exception& e) {
    FAIL() << "MRPT: " << e.what();
  }
  expect_identical_logs(native, mrpt, time_tolerance);
}

// A sensor pose: turned by `yaw`, optionally upside down (turned by pi about
// its x axis), at (x, y, z).
struct SensorPose {
  double x = 0.1, y = -0.2, z = 0.3, yaw = 0.4;
  bool upside_down = false;

  // Row-major rotation: Rz(yaw) * Rx(pi if upside down).
  void rotation(double r[3][3]) const {
    const double c = std::cos(yaw), s = std::sin(yaw);
    const double f = upside_down ? -1.0 : 1.0;
    const double m[3][3] = {{c, -s * f, 0}, {s, c * f, 0}, {0, 0, f}};
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) r[i][j] = m[i][j];
  }
};

Bytes matrix(const std::string& name, int rows, int cols,
             const std::function<double(int, int)>& at, bool floats,
             bool old_format = false) {
  Bytes b;
  b.u32(rows).u32(cols);
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c)
      floats ? b.f32(static_cast<float>(at(r, c))) : b.f64(at(r, c));
  return Bytes().obj(name, 0, b, old_format);
}

Bytes pose2d(int version, double x, double y, double phi,
             const std::string& name = "CPose2D") {
  Bytes b;
  if (version == 0)
    b.f32(static_cast<float>(x)).f32(static_cast<float>(y)).f32(
        static_cast<float>(phi));
  else
    b.f64(x).f64(y).f64(phi);
  return Bytes().obj(name, version, b);
}

Bytes pose3d(int version, const SensorPose& p, bool old_format = false) {
  double r[3][3];
  p.rotation(r);
  const double t[3] = {p.x, p.y, p.z};
  auto homogeneous = [&](int i, int j) {
    return i == 3 ? (j == 3 ? 1.0 : 0.0) : (j == 3 ? t[i] : r[i][j]);
  };
  Bytes b;
  switch (version) {
    case 0:
      b.add(matrix("CMatrix", 4, 4, homogeneous, true, old_format));
      break;
    case 1:
      b.add(matrix("CMatrixD", 4, 4, homogeneous, false, old_format));
      break;
    case 2: {
      // Rz(yaw) * Rx(pi): q = (cos(yaw/2), 0, 0, sin(yaw/2)) * (0, 1, 0, 0).
      const double c = std::cos(p.yaw / 2), s = std::sin(p.yaw / 2);
      b.f64(p.x).f64(p.y).f64(p.z);
      if (p.upside_down)
        b.f64(0).f64(c).f64(s).f64(0);
      else
        b.f64(c).f64(0).f64(0).f64(s);
      break;
    }
    default:
      b.f64(p.x).f64(p.y).f64(p.z);
      for (auto& row : r)
        for (double v : row) b.f64(v);
  }
  return Bytes().obj("CPose3D", version, b, old_format);
}

// A 4-beam scan; `k` varies the readings and the time.
Bytes scan(int version, int pose_version, int k, const SensorPose& pose,
           bool old_format = false,
           const std::string& name = "CObservation2DRangeScan") {
  const float max_range = 20.0f;
  const float ranges[4] = {1.5f + k, 20.0f, 0.0f, 3.25f + 0.5f * k};
  Bytes b;
  b.f32(static_cast<float>(M_PI / 2)).boolean(k % 2 == 0).f32(max_range);
  b.add(pose3d(pose_version, pose, old_format));
  if (version < 6)  // the sensor pose's covariance, of any size
    b.add(matrix("CMatrix", 2, 3, [](int i, int j) { return i + 0.5 * j; },
                 true, old_format));
  b.u32(4);
  for (float r : ranges) b.f32(r);
  if (version >= 1) b.u8(1).u8(0).u8(1).u8(k % 2 ? 7 : 1);  // any non-zero
  if (version >= 2) b.f32(0.02f);                            // stdError
  if (version >= 3) b.u64(133000000000000000ull + 5000000ull * k);
  if (version >= 4) b.f32(0.01f);  // beamAperture
  if (version >= 5) b.str("FRONT").f64(0.0);
  if (version >= 7) {
    b.boolean(true);  // intensities
    for (int i = 0; i < 4; ++i) b.i32(100 + i);
  }
  return Bytes().obj(name, version, b, old_format);
}

Bytes odometry(int version, int pose_version, double x, double y, double phi,
               bool encoders = true, bool velocities = true) {
  Bytes b;
  b.add(pose2d(pose_version, x, y, phi)).str("ODO").u64(133000000000000000ull);
  if (version >= 1) {
    b.boolean(encoders);
    if (encoders || version < 2) b.i32(10).i32(-20);
    b.boolean(velocities);
    if (version < 2)
      b.f32(0.5f).f32(0.1f);
    else if (velocities)
      b.f64(0.5).f64(0.0).f64(0.1);
  }
  return Bytes().obj("CObservationOdometry", version, b);
}

Bytes gaussian_pdf(int version, double x, double y, double phi) {
  Bytes b;
  b.add(pose2d(1, x, y, phi));
  if (version == 2)
    for (int i = 0; i < 6; ++i) b.f64(0.01 * (i + 1));
  else if (version == 1)
    for (int i = 0; i < 6; ++i) b.f32(0.01f * (i + 1));
  else
    b.add(matrix("CMatrix", 3, 3, [](int i, int j) { return i == j ? 0.1 : 0; },
                 true));
  return Bytes().obj("CPosePDFGaussian", version, b);
}

// A movement estimated by odometry (method 0) or scan matching (method 1).
Bytes move2d(int version, int method, double x, double y, double phi,
             int pdf_version = 2) {
  Bytes b;
  if (version <= 1) {
    b.add(gaussian_pdf(pdf_version, x, y, phi)).i32(method);
    if (version == 1)
      b.boolean(true).f32(0.3f).f32(0.2f).boolean(true).i32(5).i32(6);
    return Bytes().obj("CActionRobotMovement2D", version, b);
  }
  b.i32(method);
  if (method == 0) {
    b.add(pose2d(1, x, y, phi));
    if (version == 2) {
      for (int i = 0; i < 44; ++i) b.u8(0);
    } else if (version == 3) {
      b.i32(0).f32(1).f32(2).f32(3).f64(0.01).f64(0.002);
      b.u32(300).f32(0.1f).f32(0.2f).f32(0.3f).f32(0.4f);
    } else {
      b.i32(0);
      for (int i = 0; i < 6; ++i) b.f32(0.01f * (i + 1));
      b.u32(300).f32(0.1f).f32(0.2f).f32(0.3f).f32(0.4f);
      if (version >= 5) b.f32(0.001f).f32(0.002f);
    }
  } else {
    b.add(gaussian_pdf(pdf_version, x, y, phi));
  }
  if (version >= 7) {
    b.boolean(true).f64(0.3).f64(0.0).f64(0.2);  // velocities
    b.boolean(false);                            // no encoder ticks
  } else {
    b.boolean(true).f32(0.3f).f32(0.2f).boolean(false).i32(0).i32(0);
  }
  if (version >= 6) b.u64(133000000000000000ull);
  return Bytes().obj("CActionRobotMovement2D", version, b);
}

Bytes frame(int version, const std::vector<Bytes>& observations,
            bool old_format = false,
            const std::string& name = "CSensoryFrame") {
  Bytes b;
  if (version < 2) b.u32(77);                      // ID
  if (version == 0) b.u64(133000000012345678ull);  // the frame's time
  b.u32(static_cast<uint32_t>(observations.size()));
  for (const Bytes& o : observations) b.add(o);
  return Bytes().obj(name, version, b, old_format);
}

Bytes actions(const std::vector<Bytes>& moves) {
  Bytes b;
  b.u32(static_cast<uint32_t>(moves.size()));
  for (const Bytes& m : moves) b.add(m);
  return Bytes().obj("CActionCollection", 0, b);
}

TEST(RawlogVersions, ScansOfEveryVersionWithEverySensorPose) {
  for (int v = 0; v <= 7; ++v) {
    for (int pv = 0; pv <= 3; ++pv) {
      SCOPED_TRACE("scan version " + std::to_string(v) + ", CPose3D version " +
                   std::to_string(pv));
      SensorPose flipped;
      flipped.upside_down = true;
      flipped.yaw = -2.5;
      Bytes file;
      file.add(odometry(2, 1, 0, 0, 0)).add(scan(v, pv, 0, SensorPose()));
      file.add(odometry(2, 1, 1.0, 0.5, 4.0)).add(scan(v, pv, 1, flipped));
      // Before version 3, scans store no time and get the time of reading.
      expect_same_reading(file, v < 3 ? 60.0 : 0.0);
    }
  }
}

TEST(RawlogVersions, OdometryOfEveryVersion) {
  for (int v = 0; v <= 2; ++v) {
    for (int pv = 0; pv <= 1; ++pv) {
      for (bool extras : {false, true}) {
        SCOPED_TRACE("odometry version " + std::to_string(v) +
                     ", CPose2D version " + std::to_string(pv) +
                     (extras ? ", encoders and velocities" : ""));
        Bytes file;
        file.add(scan(7, 3, 0, SensorPose()));  // before any odometry
        file.add(odometry(v, pv, 1.0, 2.0, 0.3, extras, extras));
        file.add(scan(7, 3, 1, SensorPose()));
        // phi beyond pi: stored as is, wrapped by the reader.
        file.add(odometry(v, pv, 1.7, 2.4, 3.9, extras, extras));
        file.add(scan(7, 3, 2, SensorPose()));
        expect_same_reading(file);
      }
    }
  }
}

TEST(RawlogVersions, MovementsOfEveryVersion) {
  for (int v = 0; v <= 7; ++v) {
    for (int method : {0, 1}) {
      for (int pdf = 0; pdf <= 2; ++pdf) {
        if (method == 0 && v >= 2 && pdf != 2) continue;  // no PDF stored
        SCOPED_TRACE("movement version " + std::to_string(v) + ", method " +
                     std::to_string(method) + ", PDF version " +
                     std::to_string(pdf));
        Bytes file;
        file.add(frame(2, {scan(7, 3, 0, SensorPose())}));
        file.add(actions({move2d(v, method, 0.5, 0.1, 0.2, pdf),
                          move2d(v, method, 0.25, -0.1, 3.5, pdf)}));
        file.add(frame(2, {scan(7, 3, 1, SensorPose())}));
        file.add(actions({move2d(v, method, 1.0, 0.0, -0.5, pdf)}));
        file.add(frame(2, {scan(7, 3, 2, SensorPose())}));
        expect_same_reading(file);
      }
    }
  }
}

// Version 0 frames give all their observations the frame's time.
TEST(RawlogVersions, SensoryFramesOfEveryVersion) {
  for (int v = 0; v <= 2; ++v) {
    SCOPED_TRACE("frame version " + std::to_string(v));
    Bytes file;
    file.add(frame(v, {scan(3, 1, 0, SensorPose()),
                       odometry(2, 1, 0, 0, 0), scan(7, 3, 1, SensorPose())}));
    file.add(actions({move2d(7, 0, 0.5, 0.1, 0.2)}));
    file.add(frame(v, {scan(5, 2, 2, SensorPose())}));
    expect_same_reading(file);
  }
}

// Very old files: one CRawlog object holding every entry, and a comment.
TEST(RawlogVersions, WholeRawlogObject) {
  for (int v = 0; v <= 1; ++v) {
    SCOPED_TRACE("CRawlog version " + std::to_string(v));
    Bytes body;
    body.u32(3);
    body.add(frame(1, {scan(4, 1, 0, SensorPose())}));
    body.add(actions({move2d(4, 0, 0.5, 0.1, 0.2)}));
    body.add(frame(1, {scan(4, 1, 1, SensorPose())}));
    Bytes comment;
    comment.str("recorded in a corridor").u64(133000000000000000ull);
    body.obj("CObservationComment", 0, comment);
    expect_same_reading(Bytes().obj("CRawlog", v, body));
  }
}

// Objects from MRPT < 0.5.5: uint32 name length, int32 version, no end flag.
TEST(RawlogVersions, OldFormatObjectHeaders) {
  Bytes file;
  file.add(frame(0, {scan(1, 1, 0, SensorPose(), true)}, true));
  file.add(actions({move2d(0, 0, 0.5, 0.1, 0.2, 0)}));
  file.add(frame(0, {scan(1, 0, 1, SensorPose(), true)}, true));
  expect_same_reading(file);
}

// MRPT 2.x writes qualified class names, older MRPT plain ones.
TEST(RawlogVersions, QualifiedAndPlainClassNames) {
  Bytes file;
  file.add(frame(2, {scan(7, 3, 0, SensorPose(), false,
                          "mrpt::obs::CObservation2DRangeScan")},
                 false, "mrpt::obs::CSensoryFrame"));
  file.add(odometry(2, 1, 0.5, 0, 0));
  file.add(frame(2, {scan(7, 3, 1, SensorPose())}));
  expect_same_reading(file);
}

// What MRPT reads into a pointer of the wrong base class becomes null (a
// pose in a frame), and nulls in a frame are skipped.
TEST(RawlogVersions, ObjectsOfTheWrongKindAndNullsInFrames) {
  Bytes file;
  file.add(frame(2, {pose2d(1, 1, 2, 3), scan(7, 3, 0, SensorPose()),
                     Bytes().null_obj()}));
  file.add(actions({move2d(7, 0, 0.5, 0.1, 0.2)}));
  file.add(frame(2, {scan(7, 3, 1, SensorPose())}));
  expect_same_reading(file);
}

// MRPT 2.5.8 crashes on a null or a non-action in an action collection; the
// native reader skips them, as it does in frames.
TEST(RawlogVersions, NullsAndNonActionsInActionCollectionsAreSkipped) {
  Bytes file;
  file.add(frame(2, {scan(7, 3, 0, SensorPose())}));
  file.add(actions({frame(2, {}), Bytes().null_obj(),
                    move2d(7, 0, 0.5, 0.1, 0.2)}));
  file.add(frame(2, {scan(7, 3, 1, SensorPose())}));
  const std::string p = scratch_dir() + "/made.rawlog";
  write_bytes(p, file.bytes());
  const hmt::Log log = read_rawlog(p);
  ASSERT_EQ(log.steps.size(), 2u);
  EXPECT_EQ(log.steps[1].odometry_increment.x, 0.5);
  EXPECT_EQ(log.steps[1].odometry_increment.y, 0.1);
  EXPECT_EQ(log.steps[1].odometry_increment.theta, 0.2);
}

}  // namespace
}  // namespace hmt::io
