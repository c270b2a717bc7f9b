#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

namespace soltex::bench {

// The p-quantile (p in [0, 1]) of `values`, interpolating linearly between the order
// statistics around it (so the median of an even count is the mean of the middle two); 0 for
// no values. The sweep reports medians and quartiles, not means, because the machine it runs
// on is shared: a descheduled frame lands in the tail, not in the middle.
inline double percentile(std::vector<double> values, double p) {
  if (values.empty()) return 0.0;
  std::sort(values.begin(), values.end());
  const double position = std::clamp(p, 0.0, 1.0) * static_cast<double>(values.size() - 1);
  const auto below = static_cast<std::size_t>(std::floor(position));
  const std::size_t above = std::min(below + 1, values.size() - 1);
  const double fraction = position - static_cast<double>(below);
  return values[below] + fraction * (values[above] - values[below]);
}

inline double median(std::vector<double> values) {
  return percentile(std::move(values), 0.5);
}

}  // namespace soltex::bench
