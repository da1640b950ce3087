#include "hmt/area/sso.h"

#include <stdexcept>

namespace hmt::area {

double observation_sso(const Observation& a, const PoseGaussian& pose_a,
                       const Observation& b, const PoseGaussian& pose_b,
                       const SsoOptions& options) {
  if (a.scans.size() != b.scans.size() ||
      a.landmark_sets.size() != b.landmark_sets.size())
    throw std::invalid_argument(
        "observation_sso: the observations have different sensors");
  double sum = 0.0;
  int sensors = 0;
  for (size_t k = 0; k < a.scans.size(); ++k) {
    const PreparedScan pa(a.scans[k], options), pb(b.scans[k], options);
    if (pa.empty() && pb.empty()) continue;
    sum += scan_sso(pa, pose_a, pb, pose_b, options);
    ++sensors;
  }
  for (size_t k = 0; k < a.landmark_sets.size(); ++k) {
    if (a.landmark_sets[k].landmarks.empty() &&
        b.landmark_sets[k].landmarks.empty())
      continue;
    sum += landmark_sso(a.landmark_sets[k], pose_a, b.landmark_sets[k], pose_b,
                        options);
    ++sensors;
  }
  return sensors > 0 ? sum / sensors : 0.0;
}

}  // namespace hmt::area
