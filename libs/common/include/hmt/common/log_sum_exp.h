// log(sum_i exp(v_i)), computed relative to the largest term so that it
// neither overflows nor loses the small terms; -inf for an empty or all -inf
// input. And normalised_exp(), the probabilities such log weights give.
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

// exp(v_i) / sum_j exp(v_j) for every i: log weights made probabilities,
// through log_sum_exp for the same range and precision.
inline std::vector<double> normalised_exp(std::vector<double> v) {
  const double z = log_sum_exp(v);
  for (double& x : v) x = std::exp(x - z);
  return v;
}

}  // namespace hmt
