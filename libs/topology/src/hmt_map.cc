#include "hmt/topology/hmt_map.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "hmt/common/sole_owner.h"

namespace hmt::topology {
namespace {

std::string name(AreaId id) { return "area " + std::to_string(id); }

bool finite(const Pose2D& p) {
  return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.theta);
}

}  // namespace

void HmtMap::add_area(AreaId id, const ReferenceFrame& frame) {
  if (id == kNoArea)
    throw std::invalid_argument("HmtMap::add_area: kNoArea is not an area id");
  if (has_area(id))
    throw std::invalid_argument("HmtMap::add_area: " + name(id) +
                                " already exists");
  if (frame.parent != kNoArea && !has_area(frame.parent))
    throw std::invalid_argument("HmtMap::add_area: parent " +
                                name(frame.parent) + " of " + name(id) +
                                " does not exist");
  if (!finite(frame.origin_in_parent))
    throw std::invalid_argument("HmtMap::add_area: non-finite frame origin");
  auto a = std::make_shared<Area>();
  a->id = id;
  a->frame = frame;
  a->frame.origin_in_parent.theta = wrap_angle(frame.origin_in_parent.theta);
  areas_.emplace(id, std::move(a));
}

const Area& HmtMap::area(AreaId id) const {
  const auto it = areas_.find(id);
  if (it == areas_.end())
    throw std::out_of_range("HmtMap: unknown " + name(id));
  return *it->second;
}

std::vector<AreaId> HmtMap::area_ids() const {
  std::vector<AreaId> ids;
  ids.reserve(areas_.size());
  for (const auto& kv : areas_) ids.push_back(kv.first);
  return ids;
}

AreaId HmtMap::next_area_id() const {
  return areas_.empty() ? 0 : areas_.rbegin()->first + 1;
}

Area& HmtMap::writable(AreaId id) {
  const auto it = areas_.find(id);
  if (it == areas_.end())
    throw std::out_of_range("HmtMap: unknown " + name(id));
  // Shared with a copy of this map (another hypothesis, or a snapshot held
  // by the TSBI or TLCA thread): clone before writing.
  if (it->second.use_count() > 1) {
    it->second = std::make_shared<Area>(*it->second);
  } else {
    // Sole owner: a copy on another thread that was just released read this
    // area; pair with that release before writing in place.
    acquire_sole_ownership(it->second);
  }
  return *it->second;
}

void HmtMap::add_keyframe(AreaId id, Keyframe keyframe) {
  if (!finite(keyframe.pose))
    throw std::invalid_argument("HmtMap::add_keyframe: non-finite pose");
  if (keyframe.scan.valid.size() != keyframe.scan.ranges.size())
    throw std::invalid_argument(
        "HmtMap::add_keyframe: scan has different numbers of ranges and "
        "validity flags");
  writable(id).keyframes.push_back(std::move(keyframe));
}

bool HmtMap::has_keyframe_near(AreaId id, const Pose2D& pose, double distance,
                               double angle) const {
  for (const Keyframe& k : area(id).keyframes)
    if (within_spacing(pose - k.pose, distance, angle)) return true;
  return false;
}

void HmtMap::archive_map(AreaId id, grid::OccupancyGrid map) {
  set_map(id, std::make_shared<const grid::OccupancyGrid>(std::move(map)));
}

void HmtMap::set_map(AreaId id,
                     std::shared_ptr<const grid::OccupancyGrid> map) {
  writable(id).map = std::move(map);
}

const Arc& HmtMap::add_arc_measurement(AreaId from, AreaId to,
                                       const PoseGaussian& to_in_from) {
  if (!has_area(from) || !has_area(to))
    throw std::invalid_argument("HmtMap::add_arc_measurement: unknown " +
                                name(has_area(from) ? to : from));
  if (from == to)
    throw std::invalid_argument(
        "HmtMap::add_arc_measurement: an arc needs two distinct areas");
  if (!finite(to_in_from.mean))
    throw std::invalid_argument("HmtMap::add_arc_measurement: non-finite mean");
  require_positive_definite(to_in_from.cov, "HmtMap::add_arc_measurement");

  PoseGaussian m = from < to ? to_in_from : inverse(to_in_from);
  m.mean.theta = wrap_angle(m.mean.theta);
  const auto key = std::make_pair(std::min(from, to), std::max(from, to));
  auto it = arcs_.find(key);
  if (it == arcs_.end()) {
    Arc arc;
    arc.from = key.first;
    arc.to = key.second;
    arc.pose = m;
    arc.measurements = 1;
    return arcs_.emplace(key, arc).first->second;
  }
  Arc& arc = it->second;
  arc.pose = fuse(arc.pose, m);
  ++arc.measurements;
  return arc;
}

void HmtMap::set_arc(const Arc& arc) {
  if (!has_area(arc.from) || !has_area(arc.to))
    throw std::invalid_argument("HmtMap::set_arc: unknown " +
                                name(has_area(arc.from) ? arc.to : arc.from));
  if (arc.from == arc.to)
    throw std::invalid_argument(
        "HmtMap::set_arc: an arc needs two distinct areas");
  if (arc.measurements < 1)
    throw std::invalid_argument("HmtMap::set_arc: an arc needs a measurement");
  if (!finite(arc.pose.mean))
    throw std::invalid_argument("HmtMap::set_arc: non-finite mean");
  require_positive_definite(arc.pose.cov, "HmtMap::set_arc");
  Arc stored = arc;
  if (arc.from > arc.to) {
    stored.from = arc.to;
    stored.to = arc.from;
    stored.pose = inverse(arc.pose);
  }
  stored.pose.mean.theta = wrap_angle(stored.pose.mean.theta);
  arcs_[{stored.from, stored.to}] = stored;
}

const Arc* HmtMap::find_arc(AreaId a, AreaId b) const {
  const auto it = arcs_.find({std::min(a, b), std::max(a, b)});
  return it == arcs_.end() ? nullptr : &it->second;
}

bool HmtMap::has_arc(AreaId a, AreaId b) const {
  return find_arc(a, b) != nullptr;
}

PoseGaussian HmtMap::arc(AreaId a, AreaId b) const {
  const Arc* arc = find_arc(a, b);
  if (!arc)
    throw std::out_of_range("HmtMap: no arc between " + name(a) + " and " +
                            name(b));
  return a < b ? arc->pose : inverse(arc->pose);
}

std::vector<AreaId> HmtMap::neighbours(AreaId id) const {
  std::vector<AreaId> out;
  for (const auto& kv : arcs_) {
    if (kv.first.first == id) out.push_back(kv.first.second);
    if (kv.first.second == id) out.push_back(kv.first.first);
  }
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace hmt::topology
