#include "pareto_front.h"

namespace soltex::bench {
namespace {

bool dominates(const TimeAccuracy& a, const TimeAccuracy& b) {
  return a.ms <= b.ms && a.psnr >= b.psnr && (a.ms < b.ms || a.psnr > b.psnr);
}

}  // namespace

std::vector<bool> pareto_front(std::span<const TimeAccuracy> points) {
  std::vector<bool> front(points.size(), true);
  for (std::size_t i = 0; i < points.size(); ++i) {
    for (std::size_t j = 0; j < points.size() && front[i]; ++j) {
      if (j != i && dominates(points[j], points[i])) front[i] = false;
    }
  }
  return front;
}

}  // namespace soltex::bench
