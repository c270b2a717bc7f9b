#pragma once

#include <cstdint>
#include <glm/vec3.hpp>
#include <span>

#include "soltex/common/fractal.h"
#include "soltex/common/texture_evaluator.h"
#include "soltex/common/texture_spec.h"

// The built-in patterns (not graphs) over a batch of points or a whole grid, compiled for every
// Highway target and chosen at run time once per call (once per brick for a grid). The code is
// the per-point field expressions of pattern_fields.h in plain loops: compiled per target, the
// compiler gives a generic binary the instructions a -march=native build would use (SSE4.1's
// rounding for the many floors, AVX's wider vectors where a loop vectorises). The gradient
// fractal at one point is the vector kernel of fractal_point-inl.h for the same target. Every
// target executes the same IEEE operations in the same order (-ffp-contract=off), so all give
// the scalar path's bits.
namespace soltex::pattern_kernels {

// What the kernels need of a TextureEvaluator.
struct PatternSource {
  const TextureSpec* spec;
  const ColourRamp* ramp;        // the ramp the colour planes apply (TextureEvaluator's)
  const FractalParams* fractal;  // the pattern's fractal, nullptr for patterns without noise
  const OctavePlan* point_plan;  // plan_octaves(*fractal, 0) (empty without a fractal)
  double wood_cos_tilt_z, wood_sin_tilt_z;
};

// TextureEvaluator::sample over points, each with its footprint (sizes checked by the caller).
void sample_points(const PatternSource& source, std::span<const glm::dvec3> points,
                   std::span<const SampleFootprint> footprints, std::span<Texel> out);

// The same at one point: dispatched per call in a generic build, called directly where the
// build's own target is the best one compiled (SOLTEX_POINT_DISPATCH in noise_kernels.h).
Texel sample_point(const PatternSource& source, const glm::dvec3& p,
                   const SampleFootprint& footprint);

// TextureEvaluator::evaluate_grid's planes for a built-in pattern (sizes checked by the caller):
// `plan` is the octave plan at the filter width, `box` the hard edges' box.
void evaluate_grid(const PatternSource& source, const Grid& grid, const OctavePlan& plan,
                   const glm::dvec3& box, std::span<float> out);

// The Highway targets compiled in, and the one the kernels dispatch to now (tests force each).
int64_t compiled_targets();
int64_t dispatched_target();

}  // namespace soltex::pattern_kernels
