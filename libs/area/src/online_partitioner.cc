#include "hmt/area/online_partitioner.h"

#include <algorithm>

#include "hmt/area/spectral_bisection.h"

namespace hmt::area {

OnlinePartitioner::OnlinePartitioner(const AreaOptions& options)
    : options_(options), graph_(options) {}

int OnlinePartitioner::add_keyframe(const Keyframe& keyframe) {
  const int id = next_id_++;
  // Make room first so the window never exceeds window_size.
  while (static_cast<int>(window_.size()) >= options_.window_size) {
    graph_.remove(window_.front());
    window_.erase(window_.begin());
  }
  graph_.add(id, keyframe);
  window_.push_back(id);
  area_.push_back(id);
  return id;
}

std::vector<int> OnlinePartitioner::window() const { return window_; }

AreaDecision OnlinePartitioner::update() {
  AreaDecision d;
  const int n = static_cast<int>(window_.size());
  if (n < 2) return d;
  const WeightMatrix W = graph_.weight_matrix(window_);
  const BisectionOptions bopt{options_.partition.split_method,
                              options_.partition.min_cluster_size};
  const Bisection b = spectral_bisection(W, bopt);
  if (!b.valid) return d;
  d.ncut = b.ncut;
  if (!(b.ncut < options_.partition.tau)) return d;

  // Local index n-1 is the newest keyframe, 0 the oldest in the graph; `a`
  // always holds node 0, so the newest is in `b` unless both are in `a`.
  const auto in = [](const std::vector<int>& v, int i) {
    return std::binary_search(v.begin(), v.end(), i);
  };
  if (in(b.a, n - 1)) return d;  // newest with the oldest: same area
  const size_t min_size =
      static_cast<size_t>(options_.partition.min_cluster_size);
  if (b.a.size() < min_size || b.b.size() < min_size) return d;

  d.new_area = true;
  for (int i : b.b) d.new_area_keyframes.push_back(window_[i]);
  for (int id : area_)
    if (!std::binary_search(d.new_area_keyframes.begin(),
                            d.new_area_keyframes.end(), id))
      d.stay.push_back(id);
  for (int i : b.a) graph_.remove(window_[i]);
  window_ = d.new_area_keyframes;
  area_ = d.new_area_keyframes;
  return d;
}

}  // namespace hmt::area
