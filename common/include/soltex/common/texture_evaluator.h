#pragma once

#include <cstddef>
#include <cstdint>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <span>

#include "soltex/common/fractal.h"
#include "soltex/common/texture_spec.h"

namespace soltex {

// A regular 3D grid of points, x fastest:
//     point(i, j, k) = origin + (first + (i, j, k)) * step
// Positions are computed from the global lattice index (first + i), never by accumulating
// steps or from a shifted origin, so two grids that share a lattice point (neighbouring bricks
// sharing a face) compute it bit-identically.
struct Grid {
  glm::dvec3 origin{0.0};
  glm::dvec3 step{1.0};
  glm::ivec3 count{1};
  glm::ivec3 first{0};

  std::size_t size() const {
    return static_cast<std::size_t>(count.x) * static_cast<std::size_t>(count.y) *
           static_cast<std::size_t>(count.z);
  }
  static double coordinate(double origin, double step, int first, int i) {
    return origin + static_cast<double>(static_cast<int64_t>(first) + i) * step;
  }
  glm::dvec3 point(int i, int j, int k) const {
    return {coordinate(origin.x, step.x, first.x, i), coordinate(origin.y, step.y, first.y, j),
            coordinate(origin.z, step.z, first.z, k)};
  }
};

// One evaluated texture sample: the pattern's scalar field t in [0, 1] and its colour.
struct Texel {
  glm::vec3 colour{0.0f};
  float field = 0.0f;
};

// How widely a sample is filtered. `width` is the sample spacing in texture units: octaves of
// noise finer than it are faded to their mean. `box` is the per-axis width of the box over
// which hard edges (stripes, checkers, rings, wood grain, the colour cube's triangle waves) are
// averaged in closed form: a MIP level's spacing on every axis, or a pixel's footprint in the
// plane of the surface it sees, which has no extent along that surface's normal. Zeros sample
// the function as it is.
struct SampleFootprint {
  double width = 0.0;
  glm::dvec3 box{0.0};

  static SampleFootprint isotropic(double w) {
    const double finite = w > 0.0 ? w : 0.0;  // NaN and negative widths sample points
    return {finite, glm::dvec3(finite)};
  }
};

// Evaluates one texture at points or over grids. Construction validates the spec (throws
// SpecError) and precomputes what does not depend on the point. Thread-safe: all methods
// are const and keep their scratch space per thread.
//
// filter_width is the sample spacing in texture units: octaves of noise finer than it can
// show are faded to their mean (see fractal.h), and hard edges are averaged over a box of that
// width on every axis (SampleFootprint::isotropic); 0 samples the function as it is.
// A sample's colour is the ramp averaged over the field's values within its box, not the ramp
// of the field's average: marble or noise finer than a box takes the mean of its colours.
// sample() and evaluate_grid() give bit-identical results at the same point.
namespace pattern_kernels {
struct PatternSource;  // common/src/pattern_kernels.h
}

class TextureEvaluator {
 public:
  explicit TextureEvaluator(const TextureSpec& spec);

  const TextureSpec& spec() const { return spec_; }

  Texel sample(const glm::dvec3& p, double filter_width = 0.0) const;
  Texel sample(const glm::dvec3& p, const SampleFootprint& footprint) const;
  // Many points, each over its own footprint: out[i] is bit-identical to
  // sample(points[i], footprints[i]), but the pattern is dispatched once per call and the
  // octave plan made only for patterns with noise. Throws std::invalid_argument unless
  // footprints.size() == points.size() <= out.size().
  void sample(std::span<const glm::dvec3> points, std::span<const SampleFootprint> footprints,
              std::span<Texel> out) const;

  // Writes spec().channels.sample_count() planes of grid.size() floats each, channel-planar
  // in the order R, G, B, opacity, specular (those present). out.size() must be at least
  // sample_count() * grid.size(); throws std::invalid_argument otherwise.
  void evaluate_grid(const Grid& grid, double filter_width, std::span<float> out) const;

  // The octaves evaluated at this filter width (0 for patterns without noise).
  int evaluated_octaves(double filter_width) const;

 private:
  OctavePlan plan_for(double filter_width) const;
  pattern_kernels::PatternSource pattern_source() const;

  TextureSpec spec_;
  ColourRamp colour_ramp_;   // what the colour planes apply (applied_ramp() in the .cpp)
  FractalParams fractal_{};  // the pattern's fractal, when has_fractal_
  bool has_fractal_ = false;
  OctavePlan point_plan_;   // the plan for filter_width = 0, used most often
  glm::dvec2 wood_tilt_z_;  // cos and sin of WoodParams::tilt_z
};

}  // namespace soltex
