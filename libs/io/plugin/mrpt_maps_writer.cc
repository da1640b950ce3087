// The MRPT map-writer plugin: MRPT itself builds and serializes a grid map
// (COccupancyGridMap2D) and a simple map (CSimpleMap) from the project's map
// and keyframes, so that MRPT's tools read them as their own files. Loaded
// with dlopen by mrpt_maps.cc, only when maps are written (mrpt_maps.h).
#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/maps/COccupancyGridMap2D.h>
#include <mrpt/maps/CSimpleMap.h>
#include <mrpt/math/CMatrixFixed.h>
#include <mrpt/math/CVectorFixed.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/poses/CPose2D.h>
#include <mrpt/poses/CPose3D.h>
#include <mrpt/poses/CPose3DPDFGaussian.h>
#include <mrpt/poses/CPosePDFGaussian.h>
#include <mrpt/serialization/CArchive.h>

#include <exception>
#include <stdexcept>
#include <string>
#include <vector>

#include "mrpt_maps_plugin_abi.h"
#include "rawlog_records.h"
#include "rawlog_scan.h"

namespace hmt::io::detail {
namespace {

// The archive written through MRPT's gzip file stream, as MRPT's programs
// save maps; throws if the file cannot be created or written.
template <typename Object>
void save_gz(const Object& object, const char* path) {
  mrpt::io::CFileGZOutputStream out;
  if (!out.open(path)) throw std::runtime_error("cannot create the file");
  auto archive = mrpt::serialization::archiveFrom(out);
  archive << object;
  out.close();
}

void write_gridmap(const MrptGridMap& g, const char* path) {
  // MRPT places cell i at [x_min + i * resolution, x_min + (i + 1) * resolution).
  const float res = static_cast<float>(g.resolution);
  mrpt::maps::COccupancyGridMap2D grid(
      static_cast<float>(g.x_min), static_cast<float>(g.x_min + g.size_x * g.resolution),
      static_cast<float>(g.y_min), static_cast<float>(g.y_min + g.size_y * g.resolution), res);
  if (static_cast<int>(grid.getSizeX()) != g.size_x ||
      static_cast<int>(grid.getSizeY()) != g.size_y)
    throw std::runtime_error("MRPT sized the grid " + std::to_string(grid.getSizeX()) + " x " +
                             std::to_string(grid.getSizeY()) + " cells, not " +
                             std::to_string(g.size_x) + " x " + std::to_string(g.size_y));
  // MRPT's cells hold the probability of being free.
  for (int cy = 0; cy < g.size_y; ++cy)
    for (int cx = 0; cx < g.size_x; ++cx) grid.setCell(cx, cy, 1.0f - g.occupancy(cx, cy));
  save_gz(grid, path);
}

mrpt::obs::CObservation2DRangeScan::Ptr observation(const LaserScan& scan) {
  const ScanRecord r = to_scan_record(scan, scan.timestamp);
  auto obs = mrpt::obs::CObservation2DRangeScan::Create();
  obs->sensorLabel = "LASER";
  obs->aperture = r.aperture;
  obs->rightToLeft = r.right_to_left;
  obs->maxRange = r.max_range;
  mrpt::math::CMatrixDouble33 rot;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) rot(i, j) = r.sensor_pose.rot[i][j];
  mrpt::math::CVectorFixedDouble<3> xyz;
  xyz[0] = r.sensor_pose.x;
  xyz[1] = r.sensor_pose.y;
  xyz[2] = r.sensor_pose.z;
  obs->sensorPose = mrpt::poses::CPose3D(rot, xyz);
  obs->resizeScan(r.ranges.size());
  for (size_t i = 0; i < r.ranges.size(); ++i) {
    obs->setScanRange(i, r.ranges[i]);
    obs->setScanRangeValidity(i, r.valid[i] != 0);
  }
  obs->timestamp = mrpt::Clock::time_point(mrpt::Clock::duration(r.timestamp));
  return obs;
}

void write_simplemap(const std::vector<MapKeyframe>& keyframes, const char* path) {
  mrpt::maps::CSimpleMap map;
  for (const MapKeyframe& k : keyframes) {
    mrpt::math::CMatrixDouble33 cov;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) cov(i, j) = k.pose.cov(i, j);
    const mrpt::poses::CPosePDFGaussian pose2d(
        mrpt::poses::CPose2D(k.pose.mean.x, k.pose.mean.y, k.pose.mean.theta), cov);
    // A 3D Gaussian with z, pitch and roll exactly 0, what CSimpleMap holds.
    auto pose = mrpt::poses::CPose3DPDFGaussian::Create(pose2d);
    auto frame = mrpt::obs::CSensoryFrame::Create();
    frame->insert(observation(k.scan));
    map.insert(pose, frame);
  }
  save_gz(map, path);
}

}  // namespace
}  // namespace hmt::io::detail

extern "C" __attribute__((visibility("default"))) bool hmt_io_mrpt_write_gridmap_v1(
    const hmt::io::MrptGridMap* grid, const char* path, std::string* error) {
  try {
    hmt::io::detail::write_gridmap(*grid, path);
    return true;
  } catch (const std::exception& e) {
    *error = e.what();
    return false;
  }
}

extern "C" __attribute__((visibility("default"))) bool hmt_io_mrpt_write_simplemap_v1(
    const std::vector<hmt::io::MapKeyframe>* keyframes, const char* path, std::string* error) {
  try {
    hmt::io::detail::write_simplemap(*keyframes, path);
    return true;
  } catch (const std::exception& e) {
    *error = e.what();
    return false;
  }
}
