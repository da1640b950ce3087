// Maps and observations of the simulated worlds, shared by the TSBI tests.
#pragma once

#include <Eigen/Core>
#include <memory>
#include <vector>

#include "../../metric_slam/tests/sim_world.h"
#include "hmt/grid/occupancy_grid.h"
#include "hmt/grid/scan_insertion.h"
#include "hmt/tsbi/observations.h"

namespace hmt::tsbi::test_maps {

inline LaserScan scan_at(const std::vector<testing_sim::Segment>& world, const Pose2D& p) {
  return testing_sim::cast_scan(world, p, 361, M_PI, 30.0, nullptr, 0.0);
}

// A map of `world` in the frame whose origin is the world pose `origin`,
// from scans taken at the given world poses.
inline std::shared_ptr<const grid::OccupancyGrid> map_of(
    const std::vector<testing_sim::Segment>& world, const Pose2D& origin,
    const std::vector<Pose2D>& poses) {
  auto g = std::make_shared<grid::OccupancyGrid>(0.05);
  for (const Pose2D& p : poses)
    grid::insert_scan(*g, p - origin, scan_at(world, p), grid::InsertionOptions{});
  return g;
}

inline Eigen::Matrix3d diag(double sxy, double sth) {
  return Eigen::Vector3d(sxy * sxy, sxy * sxy, sth * sth).asDiagonal();
}

// The scans taken at `poses` (world), seen from the last one; `evidence_cell`
// > 0 counts the cells their returns fall in (gather_observations).
inline Observations observe(const std::vector<testing_sim::Segment>& world,
                            const std::vector<Pose2D>& poses, double evidence_cell = 0.0) {
  std::vector<LaserScan> scans;
  for (const Pose2D& p : poses) scans.push_back(scan_at(world, p));
  std::vector<PosedScan> posed;
  for (size_t i = 0; i < poses.size(); ++i) posed.push_back({poses[i], &scans[i]});
  Observations obs = gather_observations(posed, poses.back(), 20.0, 0.05, 600, evidence_cell);
  obs.scans.clear();  // they pointed into `scans`, which dies here
  return obs;
}

}  // namespace hmt::tsbi::test_maps
