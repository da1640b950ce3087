// The HMT map of 002 Eq. 2: an annotated graph m = ({M_i}, {Delta_ab}) whose
// nodes are areas, each with a local metric map in its own frame, and whose
// arcs carry the Gaussian relative pose between adjacent areas.
//
// Arcs, 002 Eq. 9-11 (how this code reads them; the OCR is garbled but the
// equations survive):
//   Eq. 9   Delta_ab ~ N(mu_ab, Sigma_ab): the pose of b's frame in a's frame
//           is Gaussian.
//   Eq. 10  p(Delta_ab | s^t,u^t,o^t) = prod_{j=1..L} N(Delta_ab; mu_j, S_j)
//           where L is the number of times the robot moved between a and b;
//           each crossing (or map alignment, for a loop closure) gives one
//           Gaussian measurement (mu_j, S_j), and the posterior is their
//           normalised product -- again a Gaussian, computed in closed form
//           in information form: Omega = sum_j S_j^-1,
//           mu = Omega^-1 sum_j S_j^-1 mu_j. Done here incrementally: each
//           new measurement is fused with the current estimate (fuse() in
//           pose_gaussian.h), its angle unwrapped next to the current mean.
//           In (x, y, theta) this is exactly the batch product of the L
//           measurements, each heading unwrapped next to the running mean;
//           it costs O(1) per crossing and keeps only the estimate and L.
//   Eq. 11  p({Delta} | ...) = prod_{a,b} p(Delta_ab | ...): arcs are
//           independent given the robot's HMT path, so each is fused on its
//           own and paths of arcs compose as independent Gaussians (Eq. 15,
//           shortest_paths.h).
//
// Storage. An arc is stored once, for the pair (lo, hi) with lo < hi, as the
// pose of hi's frame in lo's frame; arc(b, a) is answered with the inverse
// Gaussian (first order, pose_gaussian.h), and a measurement given as b -> a
// is inverted before it is fused. The first-order inverse is an involution
// (inverting twice gives back the same mean and covariance), so the
// direction a measurement is given in does not matter.
//
// Areas are held copy-on-write: copying an HmtMap (one per topological
// hypothesis, say) copies a table of pointers, and an area is cloned only
// when a copy changes it. An area's local map is archived as a shared,
// immutable snapshot (std::shared_ptr<const grid::OccupancyGrid>): "compact"
// here means that the snapshot shares its tiles with the particle maps it
// was taken from (grid::OccupancyGrid tiles are copy-on-write), that nothing
// can write to it, and that every copy of the map and every particle that
// re-enters the area (GridRbpf::load_area) shares those same tiles. The cell
// type is fixed by libs/grid, so no field is dropped.
//
// Containers are ordered by id, never by pointer, so iteration order (and the
// saved file) is deterministic. Not synchronised: one thread writes an
// HmtMap; distinct copies may be used from different threads.
#pragma once

#include <cstdint>
#include <limits>
#include <map>
#include <memory>
#include <utility>
#include <vector>

#include "hmt/common/pose2d.h"
#include "hmt/common/sensor_data.h"
#include "hmt/grid/occupancy_grid.h"
#include "hmt/topology/pose_gaussian.h"

namespace hmt::checkpoint {
struct Access;  // hmt/checkpoint/checkpoint.h
}  // namespace hmt::checkpoint

namespace hmt::topology {

using AreaId = uint32_t;
constexpr AreaId kNoArea = std::numeric_limits<AreaId>::max();

// A keyframe kept with its area: the robot pose in the area's frame, the
// scan taken there, and the log step it was taken at (kUnknownStep when not
// known: a keyframe read from a map file older than the step's field).
constexpr uint64_t kUnknownStep = std::numeric_limits<uint64_t>::max();
struct Keyframe {
  Pose2D pose;
  LaserScan scan;
  uint64_t step = kUnknownStep;
};

// How an area's local frame was defined. When the robot enters a new area,
// every particle takes its current pose as the origin of the new area's frame
// (GridRbpf::start_new_area); the map and the keyframes of the area are
// expressed in that frame. `parent` is the area the robot came from and
// `origin_in_parent` the new origin seen from the parent's frame at that
// moment (the first measurement of the arc parent -> area, kept as it was;
// the arc itself is refined by later fusions). The first area's frame is the
// root of the map: parent = kNoArea and the identity.
struct ReferenceFrame {
  AreaId parent = kNoArea;
  Pose2D origin_in_parent;
  uint64_t created_step = 0;  // log step at which the area was entered first
  double created_time = 0.0;  // its timestamp (log clock, seconds)
};

struct Area {
  AreaId id = 0;
  ReferenceFrame frame;
  std::vector<Keyframe> keyframes;
  // The local metric map, archived when the robot leaves the area; null
  // while it has not been archived (e.g. the current area, whose map lives
  // in the particles).
  std::shared_ptr<const grid::OccupancyGrid> map;
};

struct Arc {
  AreaId from = 0;  // from < to
  AreaId to = 0;
  PoseGaussian pose;          // pose of `to`'s frame in `from`'s frame
  uint32_t measurements = 0;  // L of Eq. 10: Gaussians fused into `pose`
};

class HmtMap {
  // Checkpoints save and restore every member, bit for bit.
  friend struct hmt::checkpoint::Access;

 public:
  // --- Areas ---
  // Adds an empty area. Throws std::invalid_argument if `id` exists, is
  // kNoArea, or frame.parent is neither kNoArea nor an existing area.
  void add_area(AreaId id, const ReferenceFrame& frame = {});
  bool has_area(AreaId id) const { return areas_.count(id) != 0; }
  // Throws std::out_of_range for an unknown id.
  const Area& area(AreaId id) const;
  std::vector<AreaId> area_ids() const;  // ascending
  size_t area_count() const { return areas_.size(); }
  // One more than the largest id (0 for an empty map).
  AreaId next_area_id() const;

  void add_keyframe(AreaId id, Keyframe keyframe);
  // Whether area `id` holds a keyframe less than `distance` metres and
  // `angle` radians from `pose` (both in the area's frame).
  bool has_keyframe_near(AreaId id, const Pose2D& pose, double distance, double angle) const;
  // Archives the area's local map (replacing any earlier one). The grid is
  // taken by value: copying an OccupancyGrid copies its tile table, not its
  // tiles, and the snapshot then shares them.
  void archive_map(AreaId id, grid::OccupancyGrid map);
  void set_map(AreaId id, std::shared_ptr<const grid::OccupancyGrid> map);

  // --- Arcs ---
  // Fuses one Gaussian measurement of the pose of `to`'s frame in `from`'s
  // frame into the arc between them (creating it on the first measurement).
  // Returns the arc as stored (canonical direction). Throws
  // std::invalid_argument for unknown areas, from == to, a non-finite mean or
  // a covariance that is not positive definite.
  const Arc& add_arc_measurement(AreaId from, AreaId to,
                                 const PoseGaussian& to_in_from);
  // Replaces (or creates) an arc, e.g. after a fine alignment or on loading;
  // same checks, and arc.measurements >= 1. A given `to` < `from` is stored
  // inverted.
  void set_arc(const Arc& arc);
  bool has_arc(AreaId a, AreaId b) const;
  // The pose of b's frame in a's frame, from the arc between them in either
  // direction. Throws std::out_of_range if a and b are not adjacent.
  PoseGaussian arc(AreaId a, AreaId b) const;
  // The stored arc of the pair (either order), or nullptr.
  const Arc* find_arc(AreaId a, AreaId b) const;
  // Keyed by (from, to) with from < to.
  const std::map<std::pair<AreaId, AreaId>, Arc>& arcs() const { return arcs_; }
  // Areas joined to `id` by an arc, ascending.
  std::vector<AreaId> neighbours(AreaId id) const;

 private:
  Area& writable(AreaId id);

  std::map<AreaId, std::shared_ptr<Area>> areas_;
  std::map<std::pair<AreaId, AreaId>, Arc> arcs_;
};

}  // namespace hmt::topology
