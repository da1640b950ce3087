// The objects of MRPT rawlogs that carry 2D laser scans and odometry, decoded
// from MRPT's binary serialization (mrpt_archive.h) in every class version
// MRPT 2.5.8 reads:
//   CSensoryFrame 0-2, CActionCollection 0, CRawlog 0-1,
//   CObservation2DRangeScan 0-7, CObservationOdometry 0-2,
//   CObservationComment 0, CActionRobotMovement2D 0-7, CPosePDFGaussian 0-2,
//   CPose2D 0-1, CPose3D 0-3, CMatrixD 0, CMatrixF (alias CMatrix) 0.
// Class names are accepted as MRPT 2.x writes them ("mrpt::obs::CSensoryFrame")
// and as older MRPT did ("CSensoryFrame").
//
// Any other class (camera images, GPS, 3D scans...) has a layout this code
// does not know, and since objects carry no length it cannot be skipped:
// reading stops with UnknownClassError, and the caller hands the file to
// MRPT itself (mrpt_fallback.h).
#pragma once

#include <stdexcept>
#include <string>
#include <vector>

#include "mrpt_archive.h"
#include "rawlog_records.h"

namespace hmt::io::detail {

struct UnknownClassError : std::runtime_error {
  explicit UnknownClassError(const std::string& name)
      : std::runtime_error("unknown class " + name), class_name(name) {}
  std::string class_name;
};

// One decoded object. Where MRPT reads a polymorphic pointer (a frame's
// observations, a collection's actions, a movement's PDF) it keeps only
// objects of the right base class and nulls the others; `children` holds
// what MRPT would keep, in order, nulls left out.
struct RawObject {
  enum class Kind {
    kNull,
    kSensoryFrame,      // children: the observations
    kActionCollection,  // children: the actions
    kRawlog,            // children: the entries (nulls included)
    kScan,              // scan
    kOdometry,          // pose
    kMove2D,            // move
    kPosePdf,           // pose: the PDF's mean
    kOther,             // read, and of no use here (poses, matrices...)
  };
  enum class Base { kNone, kObservation, kAction, kPosePdf };

  Kind kind = Kind::kNull;
  Base base = Base::kNone;
  std::string class_name;  // MRPT 2.x's name of the class, for messages
  std::vector<RawObject> children;
  ScanRecord scan;
  Pose2DRecord pose;
  MoveRecord move;
};

// Reads the next object, of any class. Throws ArchiveError for malformed or
// truncated data, UnknownClassError for a class not listed above.
RawObject read_object(ArchiveReader& ar);

}  // namespace hmt::io::detail
