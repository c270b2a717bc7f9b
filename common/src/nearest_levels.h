#pragma once

// The batch form of NearestLevelTable::level() (texture_sampler.h), compiled for each Highway
// target and dispatched at run time (nearest_levels.cpp): every threshold compared in vector
// lanes, where level() searches four of them with loads that each wait for the one before.

#include <cstddef>
#include <cstdint>

namespace soltex {

// A NearestLevelTable as the kernel reads it.
struct NearestLevelSteps {
  static constexpr std::size_t kCount = 15;
  // kCount ascending bits of the footprints that start each next level; INT32_MAX past the
  // coarsest.
  const int32_t* thresholds;
  int32_t base_level;  // footprint +0
  int32_t nan_level;
  int32_t non_positive_level;  // negative footprints and -0
};

// levels[i] = the table's level of footprints[i], for i < n.
void nearest_levels(const NearestLevelSteps& steps, const float* footprints, std::size_t n,
                    int32_t* levels);

// For tests: the targets compiled, and the one a call dispatches to now.
int64_t nearest_levels_compiled_targets();
int64_t nearest_levels_dispatched_target();

}  // namespace soltex
