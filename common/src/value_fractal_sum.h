#pragma once

#include <cmath>
#include <glm/vec3.hpp>

#include "soltex/common/fractal.h"
#include "soltex/common/noise_tables.h"
#include "soltex/common/value_noise.h"

namespace soltex::detail {

// fractal_sum at one point in the value basis, octave by octave. Inline, so that a caller
// compiled for a wider target (pattern_kernels.cpp) compiles it for that target too.
template <bool kAbsolute>
inline float value_fractal_sum(const OctavePlan& plan, const glm::dvec3& p) noexcept {
  const NoiseTables& tables = noise_tables();
  float sum = 0.0f;
  for (int k = 0; k < plan.count; ++k) {
    const Octave& octave = plan.octaves[k];
    if (octave.noise_weight == 0.0f) {
      sum += octave.mean_term;
      continue;
    }
    float noise = value_noise_in_kernel(tables, p * octave.frequency);
    if constexpr (kAbsolute) noise = std::fabs(noise);
    sum += octave.noise_weight * noise + octave.mean_term;
  }
  return sum;
}

}  // namespace soltex::detail
