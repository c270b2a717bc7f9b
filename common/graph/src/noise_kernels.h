#pragma once

#include <glm/vec3.hpp>

#include "program.h"
#include "soltex/common/fractal.h"

// The noise nodes' pieces the compiler needs too.
namespace soltex::graph {

// The mean slope of one octave of noise, per lattice unit: how much a warp by a noise of
// amplitude a widens the features it moves, per unit of a (docs/TEXTURES.md, "Node graphs").
inline constexpr double kNoiseMeanSlope = 1.0;

// The octaves of a noise node at a filter width in the node's position units: octave k has
// frequency lacunarity^k and weight diminish^k, faded as fractal.h fades octaves.
OctavePlan graph_octave_plan(const NoiseSetup& setup, double filter_width);

// How visible a lattice of unit spacing is at this filter width: 1 down to four samples per
// cell, 0 at two (the fractal octaves' rule).
float lattice_visibility(double filter_width);

// Worley distance at one point (unfiltered), and its mean over space.
float worley_point(const glm::dvec3& p, const WorleySetup& setup) noexcept;
float worley_mean(const WorleySetup& setup);

// Cell noise: the value table's entry for p's unit cell, in [0, 1].
float cell_value(const glm::dvec3& p) noexcept;

}  // namespace soltex::graph
