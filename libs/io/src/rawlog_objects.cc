#include "rawlog_objects.h"

#include "rawlog_scan.h"

#include <cctype>
#include <optional>
#include <utility>

namespace hmt::io::detail {
namespace {

using Kind = RawObject::Kind;
using Base = RawObject::Base;

enum class ClassId {
  kSensoryFrame,
  kActionCollection,
  kRawlog,
  kScan,
  kOdometry,
  kComment,
  kMove2D,
  kPosePdfGaussian,
  kPose2D,
  kPose3D,
  kMatrixD,
  kMatrixF,
};

struct KnownClass {
  ClassId id;
  const char* name;        // as MRPT 2.x registers and writes it
  const char* short_name;  // as MRPT < 2.0 wrote it
  Kind kind;
  Base base;
};

constexpr KnownClass kClasses[] = {
    {ClassId::kSensoryFrame, "mrpt::obs::CSensoryFrame", "CSensoryFrame",
     Kind::kSensoryFrame, Base::kNone},
    {ClassId::kActionCollection, "mrpt::obs::CActionCollection",
     "CActionCollection", Kind::kActionCollection, Base::kNone},
    {ClassId::kRawlog, "mrpt::obs::CRawlog", "CRawlog", Kind::kRawlog,
     Base::kNone},
    {ClassId::kScan, "mrpt::obs::CObservation2DRangeScan",
     "CObservation2DRangeScan", Kind::kScan, Base::kObservation},
    {ClassId::kOdometry, "mrpt::obs::CObservationOdometry",
     "CObservationOdometry", Kind::kOdometry, Base::kObservation},
    {ClassId::kComment, "mrpt::obs::CObservationComment",
     "CObservationComment", Kind::kOther, Base::kObservation},
    {ClassId::kMove2D, "mrpt::obs::CActionRobotMovement2D",
     "CActionRobotMovement2D", Kind::kMove2D, Base::kAction},
    {ClassId::kPosePdfGaussian, "mrpt::poses::CPosePDFGaussian",
     "CPosePDFGaussian", Kind::kPosePdf, Base::kPosePdf},
    {ClassId::kPose2D, "mrpt::poses::CPose2D", "CPose2D", Kind::kOther,
     Base::kNone},
    {ClassId::kPose3D, "mrpt::poses::CPose3D", "CPose3D", Kind::kOther,
     Base::kNone},
    {ClassId::kMatrixD, "mrpt::math::CMatrixD", "CMatrixD", Kind::kOther,
     Base::kNone},
    {ClassId::kMatrixF, "mrpt::math::CMatrixF", "CMatrixF", Kind::kOther,
     Base::kNone},
    // MRPT 2.x reads MRPT 1.x's float matrix "CMatrix" as a CMatrixF.
    {ClassId::kMatrixF, "mrpt::math::CMatrixF", "CMatrix", Kind::kOther,
     Base::kNone},
};

// A C++ class name, possibly qualified: what MRPT might have registered.
// Anything else is damage, not a class to ask MRPT about.
bool looks_like_class_name(const std::string& s) {
  bool start = true;
  for (size_t i = 0; i < s.size(); ++i) {
    const unsigned char c = static_cast<unsigned char>(s[i]);
    if (start) {
      if (!(std::isalpha(c) || c == '_')) return false;
      start = false;
    } else if (c == ':') {
      if (i + 1 >= s.size() || s[i + 1] != ':') return false;
      ++i;
      start = true;
    } else if (!(std::isalnum(c) || c == '_')) {
      return false;
    }
  }
  return !start;
}

const KnownClass& find_class(const std::string& name) {
  for (const KnownClass& k : kClasses)
    if (name == k.name || name == k.short_name) return k;
  if (looks_like_class_name(name)) throw UnknownClassError(name);
  throw ArchiveError("no class is named '" + name + "'");
}

const KnownClass& class_of(ClassId id) {
  for (const KnownClass& k : kClasses)
    if (k.id == id) return k;
  throw std::logic_error("class id missing from the table");
}

[[noreturn]] void bad_version(const ObjectHeader& h) {
  throw ArchiveError("version " + std::to_string(h.version) + " of " +
                     h.class_name + " is unknown");
}

struct Matrix {
  uint32_t rows = 0, cols = 0;
  std::vector<double> values;  // row-major
};

class Decoder {
 public:
  explicit Decoder(ArchiveReader& ar) : ar_(ar) {}

  RawObject any() {
    // Each level costs stack; real rawlogs nest five deep at most
    // (CRawlog > CSensoryFrame > scan > CPose3D > matrix), damaged ones
    // could nest until the stack overflows.
    if (++depth_ > kMaxDepth) throw ArchiveError("objects nested too deeply");
    const ObjectHeader h = ar_.header();
    RawObject o;
    if (!h.is_null()) {
      const KnownClass& k = find_class(h.class_name);
      o.kind = k.kind;
      o.base = k.base;
      o.class_name = k.name;
      body(k.id, h, o);
    }
    ar_.end(h);
    --depth_;
    return o;
  }

 private:
  static constexpr int kMaxDepth = 32;

  // A field of fixed class (MRPT's ReadObject into an existing object): any
  // other class is an error, as for MRPT.
  ObjectHeader expect(ClassId id) {
    const ObjectHeader h = ar_.header();
    const KnownClass& want = class_of(id);
    if (h.is_null())
      throw ArchiveError(std::string("null object where a ") + want.name +
                         " belongs");
    if (find_class(h.class_name).id != id)
      throw ArchiveError(h.class_name + " where a " + want.name + " belongs");
    return h;
  }

  void body(ClassId id, const ObjectHeader& h, RawObject& o) {
    Pose3DRecord unused;
    switch (id) {
      case ClassId::kSensoryFrame: sensory_frame(h, o); break;
      case ClassId::kActionCollection: action_collection(h, o); break;
      case ClassId::kRawlog: rawlog(h, o); break;
      case ClassId::kScan: scan(h, o.scan); break;
      case ClassId::kOdometry: odometry(h, o.pose); break;
      case ClassId::kComment: comment(h); break;
      case ClassId::kMove2D: move2d(h, o.move); break;
      case ClassId::kPosePdfGaussian: pose_pdf_gaussian(h, o.pose); break;
      case ClassId::kPose2D: pose2d(h, o.pose); break;
      case ClassId::kPose3D: pose3d(h, unused); break;
      case ClassId::kMatrixD: matrix(h, false, nullptr); break;
      case ClassId::kMatrixF: matrix(h, true, nullptr); break;
    }
  }

  // A polymorphic pointer field: MRPT keeps the object if it is of `base`.
  std::optional<RawObject> pointer(Base base) {
    RawObject o = any();
    if (o.kind == Kind::kNull || o.base != base) return std::nullopt;
    return o;
  }

  void sensory_frame(const ObjectHeader& h, RawObject& o) {
    if (h.version > 2) bad_version(h);
    if (h.version < 2) ar_.u32();  // a frame ID, dropped in version 2
    int64_t frame_time = 0;
    if (h.version == 0) frame_time = static_cast<int64_t>(ar_.u64());
    const uint32_t n = ar_.u32();
    for (uint32_t i = 0; i < n; ++i) {
      auto obs = pointer(Base::kObservation);
      if (!obs) continue;
      // Version 0 frames hold one time for all their observations.
      if (h.version == 0) obs->scan.timestamp = frame_time;
      o.children.push_back(std::move(*obs));
    }
  }

  void action_collection(const ObjectHeader& h, RawObject& o) {
    if (h.version != 0) bad_version(h);
    const uint32_t n = ar_.u32();
    for (uint32_t i = 0; i < n; ++i)
      if (auto a = pointer(Base::kAction)) o.children.push_back(std::move(*a));
  }

  void rawlog(const ObjectHeader& h, RawObject& o) {
    if (h.version > 1) bad_version(h);
    const uint32_t n = ar_.u32();
    for (uint32_t i = 0; i < n; ++i) o.children.push_back(any());
    const ObjectHeader comments = expect(ClassId::kComment);
    comment(comments);
    ar_.end(comments);
  }

  void comment(const ObjectHeader& h) {
    if (h.version != 0) bad_version(h);
    ar_.string();  // text
    ar_.u64();     // timestamp
  }

  void scan(const ObjectHeader& h, ScanRecord& s) {
    const uint8_t v = h.version;
    if (v > 7) bad_version(h);
    s.aperture = ar_.f32();
    s.right_to_left = ar_.boolean();
    s.max_range = ar_.f32();
    s.sensor_pose = fixed_pose3d();
    if (v < 6) fixed_matrix(ClassId::kMatrixF, nullptr);  // covSensorPose
    const uint32_t n = ar_.u32();
    ar_.array(n, s.ranges);
    if (v == 0) {
      // No flags stored: valid iff below maxRange.
      s.valid.resize(n);
      for (uint32_t i = 0; i < n; ++i)
        s.valid[i] = s.ranges[i] < s.max_range ? 1 : 0;
    } else {
      ar_.array(n, s.valid);
    }
    if (v >= 2) ar_.f32();  // stdError
    // Scans older than version 3 carry no time: MRPT leaves the one a new
    // observation is born with, the time it is read.
    s.timestamp = v >= 3 ? static_cast<int64_t>(ar_.u64()) : mrpt_now_ticks();
    if (v >= 4) {
      ar_.f32();  // beamAperture
      if (v >= 5) {
        ar_.string();  // sensorLabel
        ar_.f64();     // deltaPitch
      }
      if (v >= 7 && ar_.boolean() && n > 0) ar_.skip(uint64_t(n) * 4);  // intensities
    }
  }

  void odometry(const ObjectHeader& h, Pose2DRecord& pose) {
    const uint8_t v = h.version;
    if (v > 2) bad_version(h);
    pose = fixed_pose2d();
    ar_.string();  // sensorLabel
    ar_.u64();     // timestamp
    if (v >= 1) {
      const bool encoders = ar_.boolean();
      if (encoders || v < 2) ar_.skip(8);  // left and right ticks
      const bool velocities = ar_.boolean();
      if (v < 2)
        ar_.skip(8);  // vx, omega as floats
      else if (velocities)
        ar_.skip(24);  // TTwist2D
    }
  }

  void move2d(const ObjectHeader& h, MoveRecord& m) {
    const uint8_t v = h.version;
    if (v > 7) bad_version(h);
    if (v <= 1) {
      // The PDF first; an odometry estimate's raw reading is its mean.
      if (auto pdf = pointer(Base::kPosePdf)) {
        m.has_pdf = true;
        m.pdf_mean = pdf->pose;
      }
      m.method = ar_.i32();
      if (m.method == MoveRecord::kOdometry) {
        if (!m.has_pdf)
          throw ArchiveError("robot movement without its estimate");
        m.raw_increment = m.pdf_mean;
      }
      if (v == 1) {
        ar_.boolean();  // hasVelocities
        ar_.skip(8);    // linear and angular velocity, floats
        ar_.boolean();  // hasEncodersInfo
        ar_.skip(8);    // left and right ticks
      }
      return;
    }
    m.method = ar_.i32();
    if (m.method == MoveRecord::kOdometry) {
      m.raw_increment = fixed_pose2d();
      // The motion model's parameters (the PDF is rebuilt from them).
      if (v == 2) {
        ar_.skip(44);
      } else if (v == 3) {
        ar_.i32();      // model
        ar_.skip(12);   // 3 unused floats
        ar_.skip(16);   // minStdXY, minStdPHI (doubles in MRPT 2.x)
        ar_.u32();      // nParticlesCount
        ar_.skip(16);   // alfa1..alfa4, floats
      } else {
        ar_.i32();      // model
        ar_.skip(24);   // Gaussian a1..a4, minStdXY, minStdPHI, floats
        ar_.u32();      // nParticlesCount
        ar_.skip(16);   // alfa1..alfa4, floats
        if (v >= 5) ar_.skip(8);  // additional_std_XY, additional_std_phi
      }
    } else if (auto pdf = pointer(Base::kPosePdf)) {
      m.has_pdf = true;
      m.pdf_mean = pdf->pose;
    }
    const bool velocities = ar_.boolean();
    if (v >= 7) {
      if (velocities) ar_.skip(24);  // TTwist2D
    } else {
      ar_.skip(8);  // linear and angular velocity, floats
    }
    const bool encoders = ar_.boolean();
    if (v < 7 || encoders) ar_.skip(8);  // left and right ticks
    if (v >= 6) ar_.u64();               // timestamp
  }

  void pose_pdf_gaussian(const ObjectHeader& h, Pose2DRecord& mean) {
    if (h.version > 2) bad_version(h);
    mean = fixed_pose2d();
    if (h.version == 2)
      ar_.skip(6 * 8);  // upper triangle of the covariance, doubles
    else if (h.version == 1)
      ar_.skip(6 * 4);  // ... floats
    else
      fixed_matrix(ClassId::kMatrixF, nullptr, 3, 3);
  }

  void pose2d(const ObjectHeader& h, Pose2DRecord& p) {
    if (h.version == 0) {
      p.x = ar_.f32();
      p.y = ar_.f32();
      p.phi = ar_.f32();
    } else if (h.version == 1) {
      p.x = ar_.f64();
      p.y = ar_.f64();
      p.phi = ar_.f64();
    } else {
      bad_version(h);
    }
  }

  Pose2DRecord fixed_pose2d() {
    const ObjectHeader h = expect(ClassId::kPose2D);
    Pose2DRecord p;
    pose2d(h, p);
    ar_.end(h);
    return p;
  }

  void pose3d(const ObjectHeader& h, Pose3DRecord& p) {
    switch (h.version) {
      case 0:
      case 1: {
        // A 4x4 homogeneous matrix, of floats (0) or doubles (1).
        Matrix m;
        fixed_matrix(h.version == 0 ? ClassId::kMatrixF : ClassId::kMatrixD,
                     &m, 4, 4);
        for (int r = 0; r < 3; ++r)
          for (int c = 0; c < 3; ++c) p.rot[r][c] = m.values[r * 4 + c];
        p.x = m.values[3];
        p.y = m.values[7];
        p.z = m.values[11];
        break;
      }
      case 2: {
        // x y z, then the quaternion r x y z; MRPT's
        // CQuaternion::rotationMatrixNoResize(), term by term.
        p.x = ar_.f64();
        p.y = ar_.f64();
        p.z = ar_.f64();
        const double qr = ar_.f64(), qx = ar_.f64(), qy = ar_.f64(),
                     qz = ar_.f64();
        p.rot[0][0] = qr * qr + qx * qx - qy * qy - qz * qz;
        p.rot[0][1] = 2 * (qx * qy - qr * qz);
        p.rot[0][2] = 2 * (qz * qx + qr * qy);
        p.rot[1][0] = 2 * (qx * qy + qr * qz);
        p.rot[1][1] = qr * qr - qx * qx + qy * qy - qz * qz;
        p.rot[1][2] = 2 * (qy * qz - qr * qx);
        p.rot[2][0] = 2 * (qz * qx - qr * qy);
        p.rot[2][1] = 2 * (qy * qz + qr * qx);
        p.rot[2][2] = qr * qr - qx * qx - qy * qy + qz * qz;
        break;
      }
      case 3:
        // x y z, then the rotation matrix row by row.
        p.x = ar_.f64();
        p.y = ar_.f64();
        p.z = ar_.f64();
        for (auto& row : p.rot)
          for (double& v : row) v = ar_.f64();
        break;
      default:
        bad_version(h);
    }
  }

  Pose3DRecord fixed_pose3d() {
    const ObjectHeader h = expect(ClassId::kPose3D);
    Pose3DRecord p;
    pose3d(h, p);
    ar_.end(h);
    return p;
  }

  // A CMatrixD (doubles) or CMatrixF (floats): rows, cols, then the values
  // row by row, stored in `out` if given. `rows` x `cols` is required when
  // given (MRPT asserts the size of fixed-size matrices).
  void matrix(const ObjectHeader& h, bool floats, Matrix* out,
              uint32_t rows = 0, uint32_t cols = 0) {
    if (h.version != 0) bad_version(h);
    const uint32_t r = ar_.u32(), c = ar_.u32();
    if (rows > 0 && (r != rows || c != cols))
      throw ArchiveError("a " + std::to_string(r) + "x" + std::to_string(c) +
                         " matrix where a " + std::to_string(rows) + "x" +
                         std::to_string(cols) + " one belongs");
    const uint64_t n = uint64_t(r) * c;
    if (!out) return ar_.skip(n * (floats ? 4 : 8));
    out->rows = r;
    out->cols = c;
    if (floats) {
      std::vector<float> f;
      ar_.array(n, f);
      out->values.assign(f.begin(), f.end());
    } else {
      ar_.array(n, out->values);
    }
  }

  // A matrix field (CMatrixF or CMatrixD as `id` says).
  void fixed_matrix(ClassId id, Matrix* out, uint32_t rows = 0,
                    uint32_t cols = 0) {
    const ObjectHeader h = expect(id);
    matrix(h, id == ClassId::kMatrixF, out, rows, cols);
    ar_.end(h);
  }

  ArchiveReader& ar_;
  int depth_ = 0;
};

}  // namespace

RawObject read_object(ArchiveReader& ar) { return Decoder(ar).any(); }

}  // namespace hmt::io::detail
