#pragma once

#include <span>
#include <vector>

namespace soltex::bench {

struct TimeAccuracy {
  double ms = 0.0;    // lower is better
  double psnr = 0.0;  // higher is better
};

// For each point, whether it is on the Pareto front: no other point is at least as fast and
// at least as accurate, and strictly better in one of the two. The rest are never worth
// choosing: some point on the front is at least as good in both.
std::vector<bool> pareto_front(std::span<const TimeAccuracy> points);

}  // namespace soltex::bench
