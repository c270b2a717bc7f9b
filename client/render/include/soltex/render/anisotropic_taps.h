#pragma once

#include <glm/vec3.hpp>

#include "soltex/common/check.h"

namespace soltex::render {

// The most taps a pixel may take (RenderOptions::anisotropy's bound).
inline constexpr int kMaxTaps = 16;

// Anisotropic lookups. A pixel seen at a grazing angle covers a long, thin patch of texture: one
// lookup over a box as wide as the long side blurs it across the short side too (a floor's
// stripes fade to grey towards the horizon, where the supersampled reference keeps them). It
// takes n lookups instead ("taps"), each at the level of the long side divided by n, spaced
// along the long side and averaged, the scheme GPUs use for anisotropic filtering
// (EXT_texture_filter_anisotropic): n is the ratio of the long side to the short one, rounded,
// at most `most`.

// The taps a pixel takes: 1 below a ratio of 2, where the footprint has no direction (a NaN
// ratio: a cap, an unbounded footprint) and when `most` is 1. Below 2 one lookup blurs across
// by less than a level (trilinear's rounding to the nearest level already accepts up to a
// factor 1.41), and taps would cost bricks a level finer over a whole moderately slanted
// floor: the default scene's turbulence floor, at ratios 1.5 to 2, fetched 3,499 bricks from
// 2 on, 4,626 from 1.5 and 1,551 with none, for 39.53, 39.78 and 39.37 dB
// (docs/PERFORMANCE.md, "Frame targets", paragraph 25).
// Written without branches (selects and a clamp before the conversion, so a NaN or infinite
// ratio never reaches it): the tile shader counts a whole row's taps in one vectorized loop.
inline int tap_count(float footprint, float minor, int most) {
  const float ratio = footprint / minor;
  const float largest = static_cast<float>(most);
  const float clamped = ratio >= 2.0f ? (ratio < largest ? ratio : largest) : 1.0f;
  return static_cast<int>(clamped + 0.5f);
}

namespace taps_detail {
// Tap k of n's offset (k + 0.5) / n - 0.5 and a tap's weight 1 / n, for every n <= kMaxTaps,
// made at compile time (the same correctly rounded operations as at run time): a tapped
// pixel costs no division.
struct TapTables {
  double offset[kMaxTaps + 1][kMaxTaps] = {};
  float weight[kMaxTaps + 1] = {};
  constexpr TapTables() {
    for (int n = 1; n <= kMaxTaps; ++n) {
      weight[n] = 1.0f / static_cast<float>(n);
      for (int k = 0; k < n; ++k) {
        offset[n][k] = (static_cast<double>(k) + 0.5) / static_cast<double>(n) - 0.5;
      }
    }
  }
};
inline constexpr TapTables kTapTables;
}  // namespace taps_detail

// Tap k of n: spread evenly over the long side `axis` (a vector as long as it), centred on p.
inline glm::dvec3 tap_position(const glm::dvec3& p, const glm::vec3& axis, int k, int n) {
  SOLTEX_DCHECK(n >= 1 && n <= kMaxTaps && k >= 0 && k < n);
  return p + glm::dvec3(axis) * taps_detail::kTapTables.offset[n][k];
}

// The footprint each of n taps covers, its level's footprint: the long side over n (n = 1:
// the footprint itself, bit for bit).
inline float tap_share(float footprint, int n) {
  return footprint / static_cast<float>(n);
}

// One tap's weight in the average of n: 1 / n.
inline float tap_weight(int n) {
  SOLTEX_DCHECK(n >= 1 && n <= kMaxTaps);
  return taps_detail::kTapTables.weight[n];
}

}  // namespace soltex::render
