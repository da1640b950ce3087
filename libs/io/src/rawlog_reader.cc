#include <cmath>
#include <filesystem>
#include <new>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/obs/CRawlog.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/serialization/CArchive.h>

#include "gz_stream.h"
#include "hmt/common/error.h"
#include "hmt/common/files.h"
#include "hmt/io/rawlog.h"
#include "mrpt_scan.h"
#include "rawlog_reader.h"

namespace hmt::io {
namespace detail {
namespace {

using mrpt::obs::CActionCollection;
using mrpt::obs::CActionRobotMovement2D;
using mrpt::obs::CObservation;
using mrpt::obs::CObservation2DRangeScan;
using mrpt::obs::CObservationOdometry;
using mrpt::obs::CRawlog;
using mrpt::obs::CSensoryFrame;
using mrpt::serialization::CSerializable;

Pose2D to_pose(const mrpt::poses::CPose2D& p) {
  return Pose2D(p.x(), p.y(), wrap_angle(p.phi()));
}

bool finite(const Pose2D& p) {
  return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.theta);
}

// Collects scans and odometry in file order. Both odometry sources are kept
// until the end, since which one a file uses is only known then.
class RawlogCollector {
 public:
  explicit RawlogCollector(const std::string& path) : path_(path) {}

  void add_entry(const CSerializable::Ptr& obj, size_t entry) {
    entry_ = entry;
    if (auto sf = std::dynamic_pointer_cast<CSensoryFrame>(obj)) {
      for (const auto& o : *sf) add_observation(o);
    } else if (auto acts = std::dynamic_pointer_cast<CActionCollection>(obj)) {
      for (const auto& a : *acts) add_action(a.get_ptr());
    } else if (auto o = std::dynamic_pointer_cast<CObservation>(obj)) {
      add_observation(o);
    } else if (auto raw = std::dynamic_pointer_cast<CRawlog>(obj)) {
      // Very old files hold a whole CRawlog object instead of a sequence.
      for (size_t i = 0; i < raw->size(); ++i) {
        auto inner = raw->getAsGeneric(i);
        if (std::dynamic_pointer_cast<CRawlog>(inner)) not_an_entry(inner);
        add_entry(inner, entry);
      }
    } else {
      not_an_entry(obj);
    }
  }

  hmt::Log finish(size_t entries) const {
    if (scans_.empty())
      throw InputError(prefix() + "holds no 2D laser scans (" +
                       std::to_string(entries) + " entries read)");
    const bool use_actions = any_action_;
    if (!use_actions && !first_odometry_)
      throw InputError(prefix() + "holds " + std::to_string(scans_.size()) +
                       " laser scans but no odometry (neither "
                       "CActionRobotMovement2D nor CObservationOdometry)");
    hmt::Log log;
    log.source = path_;
    log.steps.reserve(scans_.size());
    // Observations-only files: each scan takes the latest odometry reading
    // before it in the file (no interpolation). File order rather than
    // timestamps, because logs converted from other formats can carry
    // rounded or non-monotonic clocks; MRPT's grabbers write observations in
    // time order, so for them the two agree. Scans before the first odometry
    // reading take that first reading (the robot has not been seen moving).
    Pose2D prev_odo;
    for (size_t k = 0; k < scans_.size(); ++k) {
      const PendingScan& s = scans_[k];
      LogStep step;
      step.timestamp = s.scan.timestamp;
      step.scan = s.scan;
      const Pose2D odo =
          use_actions ? Pose2D() : s.odometry.value_or(*first_odometry_);
      if (k > 0) {
        step.has_odometry = true;
        step.odometry_increment =
            use_actions ? s.action_increment : odo - prev_odo;
      }
      prev_odo = odo;
      log.steps.push_back(std::move(step));
    }
    return log;
  }

 private:
  struct PendingScan {
    hmt::LaserScan scan;
    Pose2D action_increment;           // composed actions since last scan
    std::optional<Pose2D> odometry;    // latest CObservationOdometry
  };

  std::string prefix() const { return "rawlog '" + path_ + "' "; }

  [[noreturn]] void not_an_entry(const CSerializable::Ptr& obj) const {
    throw InputError(prefix() + "entry " + std::to_string(entry_) + " is a " +
                     obj->GetRuntimeClass()->className +
                     ", not a rawlog entry (CSensoryFrame, CActionCollection "
                     "or CObservation)");
  }

  void add_action(const mrpt::obs::CAction::Ptr& a) {
    auto mv = std::dynamic_pointer_cast<CActionRobotMovement2D>(a);
    if (!mv) return;  // e.g. 3D movements: not used
    // The raw odometry reading is only filled in for odometry-based
    // estimates; otherwise (scan matching) the PDF's mean is the estimate.
    Pose2D inc;
    if (mv->estimationMethod == CActionRobotMovement2D::emOdometry) {
      inc = to_pose(mv->rawOdometryIncrementReading);
    } else {
      if (!mv->poseChange.get_ptr())
        throw InputError(prefix() + "entry " + std::to_string(entry_) +
                         " holds a robot movement without an estimate");
      inc = to_pose(mv->poseChange->getMeanVal());
    }
    if (!finite(inc))
      throw InputError(prefix() + "entry " + std::to_string(entry_) +
                       " holds a non-finite odometry increment");
    pending_increment_ = pending_increment_ + inc;
    any_action_ = true;
  }

  void add_observation(const CObservation::Ptr& o) {
    if (auto scan = std::dynamic_pointer_cast<CObservation2DRangeScan>(o)) {
      PendingScan p;
      try {
        p.scan = from_mrpt_scan(*scan);
      } catch (const std::invalid_argument& e) {
        throw InputError(prefix() + "scan " + std::to_string(scans_.size()) +
                         " (entry " + std::to_string(entry_) +
                         ") is unusable: " + e.what());
      }
      p.action_increment = pending_increment_;
      p.odometry = latest_odometry_;
      pending_increment_ = Pose2D();
      scans_.push_back(std::move(p));
    } else if (auto odo = std::dynamic_pointer_cast<CObservationOdometry>(o)) {
      const Pose2D pose = to_pose(odo->odometry);
      if (!finite(pose))
        throw InputError(prefix() + "entry " + std::to_string(entry_) +
                         " holds a non-finite odometry pose");
      latest_odometry_ = pose;
      if (!first_odometry_) first_odometry_ = pose;
    }
    // Any other observation type is of no use here.
  }

  std::string path_;
  size_t entry_ = 0;
  std::vector<PendingScan> scans_;
  Pose2D pending_increment_;
  bool any_action_ = false;
  std::optional<Pose2D> latest_odometry_;
  std::optional<Pose2D> first_odometry_;
};

}  // namespace

hmt::Log read_rawlog(const std::string& path, bool chosen_by_content) {
  require_readable_file(path, "input log");
  if (std::filesystem::file_size(path) == 0)
    throw InputError("input log '" + path + "' is empty");

  GzInputStream in(path);
  auto archive = mrpt::serialization::archiveFrom(in);
  RawlogCollector collector(path);
  const std::string prefix = "rawlog '" + path + "' ";
  size_t entry = 0;
  for (;; ++entry) {
    if (in.at_end()) {
      const std::string zerr = in.compression_error();
      if (!zerr.empty())
        throw InputError(prefix + "is a damaged gzip file (zlib: " + zerr +
                         ", after " + std::to_string(entry) + " entries)");
      break;
    }
    CSerializable::Ptr obj;
    try {
      obj = archive.ReadObject();
    } catch (const std::exception& e) {
      // MRPT reports a clean end and a cut inside an object alike; at_end()
      // above already handled the clean end, so this is damage.
      const std::string zerr = in.compression_error();
      if (!zerr.empty())
        throw InputError(prefix + "is a damaged gzip file (zlib: " + zerr +
                         ", found while reading entry " +
                         std::to_string(entry) + ")");
      // Input left over: the object itself is wrong, and if it is the
      // first, the file is most likely not a rawlog at all.
      const bool cut_short = in.at_end();
      if (entry == 0 && !cut_short)
        throw InputError(
            (chosen_by_content
                 ? "input log '" + path +
                       "' is neither a CARMEN log nor an MRPT rawlog"
                 : prefix + "is not an MRPT rawlog") +
            " (its first object cannot be read)");
      const bool bad_alloc = dynamic_cast<const std::bad_alloc*>(&e);
      throw InputError(prefix + (cut_short ? "is truncated" : "is corrupt") +
                       ": entry " + std::to_string(entry) +
                       " cannot be read" + (bad_alloc ? " (absurd size)" : ""));
    }
    if (!obj)  // a serialized null pointer
      throw InputError(prefix + "entry " + std::to_string(entry) +
                       " is an empty object");
    collector.add_entry(obj, entry);
  }
  return collector.finish(entry);
}

}  // namespace detail

hmt::Log read_rawlog(const std::string& path) {
  return detail::read_rawlog(path, false);
}

}  // namespace hmt::io
