#include "soltex/common/brick_layout.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "soltex/common/spec_error.h"

namespace soltex {

BrickLayout::BrickLayout(const Volume& volume, int brick_size)
    : volume_(validated(volume)), brick_size_(brick_size), brick_shift_(0) {
  if (brick_size != 8 && brick_size != 16) {
    throw SpecError("brick_size", std::to_string(brick_size), "must be 8 or 16");
  }
  brick_shift_ = brick_size == 8 ? 3 : 4;
  if (volume_.finest_level_log2 < brick_shift_) {
    throw SpecError("volume.finest_level_log2", std::to_string(volume_.finest_level_log2),
                    "must be at least log2(brick_size) = " + std::to_string(brick_shift_) +
                        " so that the coarsest level is one whole brick");
  }
  finest_spacing_ = (volume_.max - volume_.min) / static_cast<double>(cells_per_axis(0));
}

glm::dvec3 BrickLayout::spacing(int level) const {
  return {std::ldexp(finest_spacing_.x, level), std::ldexp(finest_spacing_.y, level),
          std::ldexp(finest_spacing_.z, level)};
}

double BrickLayout::filter_width(int level) const {
  const glm::dvec3 h = spacing(level);
  return std::max({h.x, h.y, h.z});
}

bool BrickLayout::contains(int level, const glm::ivec3& brick) const {
  if (level < 0 || level > coarsest_level()) return false;
  const int n = bricks_per_axis(level);
  return brick.x >= 0 && brick.y >= 0 && brick.z >= 0 && brick.x < n && brick.y < n && brick.z < n;
}

Grid BrickLayout::sample_grid(int level, const glm::ivec3& brick) const {
  Grid grid;
  grid.origin = volume_.min;
  grid.step = spacing(level);
  grid.count = glm::ivec3(samples_per_axis());
  grid.first = brick * brick_size_;
  return grid;
}

glm::dvec3 BrickLayout::sample_coordinate(const glm::dvec3& p, int level) const {
  return (p - volume_.min) / spacing(level);
}

}  // namespace soltex
