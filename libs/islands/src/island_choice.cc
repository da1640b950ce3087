#include "hmt/islands/island_choice.h"

#include <algorithm>
#include <cmath>

namespace hmt::islands {

std::vector<Island> choose_islands(const OccupancyRaster& map, const DistinctivenessMap& d,
                                   double threshold, double min_distance) {
  std::vector<size_t> order;
  for (size_t k = 0; k < d.r.size(); ++k)
    if (!std::isnan(d.r[k]) && d.r[k] >= threshold) order.push_back(k);
  std::stable_sort(order.begin(), order.end(),
                   [&](size_t a, size_t b) { return d.r[a] > d.r[b]; });
  const double min2 = (min_distance / map.resolution) * (min_distance / map.resolution);
  std::vector<Island> out;
  for (size_t k : order) {
    const int i = static_cast<int>(k % map.width), j = static_cast<int>(k / map.width);
    bool far = true;
    for (const Island& o : out) {
      const double dx = i - o.i, dy = j - o.j;
      if (dx * dx + dy * dy < min2) {
        far = false;
        break;
      }
    }
    if (!far) continue;
    Island is;
    is.id = static_cast<int>(out.size()) + 1;
    is.i = i;
    is.j = j;
    is.x = map.x_of(i);
    is.y = map.y_of(j);
    is.r = d.r[k];
    out.push_back(is);
  }
  return out;
}

}  // namespace hmt::islands
