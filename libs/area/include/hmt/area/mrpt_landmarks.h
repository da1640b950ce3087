// Adapter from MRPT's range-bearing landmark observation to the plain
// LandmarkObservation of landmark_sso.h. In its own library, hmt_area_mrpt,
// so that hmt_area does not load MRPT; MRPT stays private to it: this header
// only forward-declares the MRPT class.
#pragma once

#include "hmt/area/landmark_sso.h"

namespace mrpt::obs {
class CObservationBearingRange;
}

namespace hmt::area {

// Each measurement (range, yaw) becomes a Gaussian in the robot frame: the
// mean through the sensor's pose on the robot (projected to the plane: x, y,
// yaw), the covariance by first-order propagation of the (range, yaw) noise —
// the per-measurement covariance when the observation flags
// validCovariances, the observation's sensor_std_range / sensor_std_yaw
// otherwise. Pitch is ignored (a 2D sensor has pitch 0). Measurements with a
// non-finite or non-positive range are skipped.
LandmarkObservation from_mrpt(const mrpt::obs::CObservationBearingRange& obs);

}  // namespace hmt::area
