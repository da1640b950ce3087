// log(sum_i exp(v_i)), computed relative to the largest term so that it
// neither overflows nor loses the small terms; -inf for an empty or all -inf
// input.
#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

namespace hmt {

inline double log_sum_exp(const std::vector<double>& v) {
  double m = -INFINITY;
  for (double x : v) m = std::max(m, x);
  if (!std::isfinite(m)) return m;
  double s = 0.0;
  for (double x : v) s += std::exp(x - m);
  return m + std::log(s);
}

}  // namespace hmt
