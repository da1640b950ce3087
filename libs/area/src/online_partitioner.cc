#include "hmt/area/online_partitioner.h"

#include <algorithm>

#include "hmt/area/placement.h"
#include "hmt/area/spectral_bisection.h"

namespace hmt::area {

OnlinePartitioner::OnlinePartitioner(const AreaOptions& options)
    : options_(options),
      graph_(options, std::make_shared<WorkerPool>(WorkerPool::threads_for(options.threads))) {}

int OnlinePartitioner::add_keyframe(const Keyframe& keyframe) {
  const int id = next_id_++;
  // Make room first so the window never exceeds window_size.
  while (static_cast<int>(window_.size()) >= options_.window_size) {
    graph_.remove(window_.front());
    window_.erase(window_.begin());
  }
  newest_uncertainty_ = keyframe.uncertainty;
  newest_distinctiveness_ = keyframe.distinctiveness;
  graph_.add(id, keyframe);
  window_.push_back(id);
  area_.push_back(id);
  return id;
}

std::vector<int> OnlinePartitioner::window() const { return window_; }

AreaDecision OnlinePartitioner::update() {
  AreaDecision d = decide();
  d.oldest_in_window = window_.empty() ? next_id_ : window_.front();
  return d;
}

AreaDecision OnlinePartitioner::decide() {
  AreaDecision d;
  const int n = static_cast<int>(window_.size());
  if (n < 2) return d;
  const PlacementOptions& po = options_.placement;
  // Eq. 3 of 003 at the newest keyframe, with the scan's R as the one model.
  const auto criterion = [&] {
    return placement_fires(newest_uncertainty_, {newest_distinctiveness_}, {po.threshold},
                           po.e_min);
  };
  const auto in = [](const std::vector<int>& v, int i) {
    return std::binary_search(v.begin(), v.end(), i);
  };
  if (po.policy == Placement::kIslands) {
    // The criterion alone decides when. Which keyframes form the new area
    // is still the graph's answer: the side of the bisection holding the
    // newest keyframe (whatever its Ncut), so that the new area starts with
    // the observations of the place just reached, which TSBI compares with
    // the known areas; the newest keyframe alone when that side also holds
    // the oldest (or there is no valid bisection).
    if (!criterion()) return d;
    const Bisection b = bisect();
    if (b.valid) d.ncut = b.ncut;
    std::vector<int> local{n - 1};
    if (b.valid && !in(b.a, n - 1)) local = b.b;
    split(local, d);
    return d;
  }
  const Bisection b = bisect();
  if (!b.valid) return d;
  d.ncut = b.ncut;
  if (!(b.ncut < options_.partition.tau)) return d;

  // Local index n-1 is the newest keyframe, 0 the oldest in the graph; `a`
  // always holds node 0, so the newest is in `b` unless both are in `a`.
  if (in(b.a, n - 1)) return d;  // newest with the oldest: same area
  const size_t min_size =
      static_cast<size_t>(options_.partition.min_cluster_size);
  if (b.a.size() < min_size || b.b.size() < min_size) return d;
  // Both: the cut proposes where, the criterion decides whether.
  if (po.policy == Placement::kBoth && !criterion()) return d;

  split(b.b, d);
  return d;
}

Bisection OnlinePartitioner::bisect() const {
  return spectral_bisection(graph_.weight_matrix(window_),
                            BisectionOptions{options_.partition.split_method,
                                             options_.partition.min_cluster_size});
}

void OnlinePartitioner::split(const std::vector<int>& local, AreaDecision& d) {
  d.new_area = true;
  for (int i : local) d.new_area_keyframes.push_back(window_[i]);
  for (int id : area_)
    if (!std::binary_search(d.new_area_keyframes.begin(),
                            d.new_area_keyframes.end(), id))
      d.stay.push_back(id);
  for (int id : window_)
    if (!std::binary_search(d.new_area_keyframes.begin(), d.new_area_keyframes.end(), id))
      graph_.remove(id);
  window_ = d.new_area_keyframes;
  area_ = d.new_area_keyframes;
}

AreaDecision OnlinePartitioner::end_of_log() {
  AreaDecision d;
  const int n = static_cast<int>(window_.size());
  if (n >= 2) {
    const Bisection b = bisect();
    // tau is not asked: the question is no longer whether the robot has
    // entered another area but whether the place it ended in is one already
    // known. That place is the bisection's side holding the newest keyframe
    // when it does not hold the oldest (as at any new-area event); when it
    // does, the robot came back towards where the area began, and the place
    // is that side's keyframes since the robot last was on the other side.
    if (b.valid) {  // both sides hold a keyframe
      std::vector<int> local;
      if (!std::binary_search(b.a.begin(), b.a.end(), n - 1)) {
        local = b.b;
      } else {
        const int last_other = b.b.back();
        for (int i : b.a)
          if (i > last_other) local.push_back(i);
      }
      if (local.size() >= static_cast<size_t>(options_.partition.min_cluster_size)) {
        d.ncut = b.ncut;
        split(local, d);
      }
    }
  }
  d.oldest_in_window = window_.empty() ? next_id_ : window_.front();
  return d;
}

}  // namespace hmt::area
