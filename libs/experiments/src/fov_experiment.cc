#include "hmt/experiments/fov_experiment.h"

#include <chrono>
#include <stdexcept>

#include "hmt/area/offline_grouping.h"
#include "hmt/area/partition.h"

namespace hmt::experiments {

void FovOptions::validate() const {
  if (!(step > 0.0)) throw std::invalid_argument("field of view: step must be > 0");
  if (!(turn_step > 0.0))
    throw std::invalid_argument("field of view: turn_step must be > 0");
  if (taus.empty()) throw std::invalid_argument("field of view: no tau given");
  for (double t : taus)
    if (!(t >= 0.0 && t <= 2.0))
      throw std::invalid_argument("field of view: every tau must be in [0, 2]");
  area.validate("area");
}

std::vector<FovResult> run_field_of_view(const World& world,
                                         const std::vector<Pose2D>& poses,
                                         const std::vector<RangeSensor>& sensors,
                                         const FovOptions& o) {
  o.validate();
  using Clock = std::chrono::steady_clock;
  std::vector<FovResult> out;
  for (const RangeSensor& s : sensors) {
    const auto keyframes = simulate_keyframes(world, poses, s);
    const auto t0 = Clock::now();
    const area::WeightMatrix W = area::sso_weight_matrix(keyframes, o.area);
    const double sso_seconds = std::chrono::duration<double>(Clock::now() - t0).count();
    const int n = static_cast<int>(keyframes.size());
    for (double tau : o.taus) {
      const auto t1 = Clock::now();
      area::PartitionOptions p = o.area.partition;
      p.tau = tau;
      const auto groups = area::recursive_partition(W, p).groups;
      FovResult r;
      r.sensor = s.name;
      r.fov_deg = s.fov * 180.0 / M_PI;
      r.beams = s.beams;
      r.max_range = s.max_range;
      r.tau = tau;
      r.keyframes = n;
      r.edges = static_cast<long>(W.nonZeros() / 2);
      r.mean_degree = n > 0 ? W.sum() / n : 0.0;
      r.areas = static_cast<int>(groups.size());
      r.labels = area::group_labels(groups, n);
      r.seconds = sso_seconds + std::chrono::duration<double>(Clock::now() - t1).count();
      out.push_back(std::move(r));
    }
  }
  return out;
}

}  // namespace hmt::experiments
