// The built-in patterns' batch kernels (pattern_kernels.cpp), compiled per Highway target and
// dispatched at run time: every target the CPU runs, forced in turn, against the scalar
// definition written out here from pattern_fields.h and the noise functions.

// As in noise_kernels.cpp: Highway 1.0.3 needs this to accept a -march=native baseline that
// includes AVX3_DL.
#ifndef HWY_WANT_AVX3_DL
#define HWY_WANT_AVX3_DL
#endif

#include "pattern_kernels.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "dispatch_targets.h"
#include "pattern_fields.h"
#include "soltex/common/gradient_noise.h"
#include "soltex/common/texture_evaluator.h"
#include "soltex/common/value_noise.h"

namespace soltex {
namespace {

std::vector<int64_t> targets_to_run() {
  return test::targets_to_run(pattern_kernels::compiled_targets());
}

constexpr double kNan = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

// Equal bits, or both NaN (a NaN's payload is not part of any result's contract).
bool same(float a, float b) {
  if (std::isnan(a) && std::isnan(b)) return true;
  return std::memcmp(&a, &b, sizeof a) == 0;
}

// fractal_sum's definition, octave by octave through the scalar noise functions.
float scalar_fractal_sum(const OctavePlan& plan, const glm::dvec3& p) {
  float sum = 0.0f;
  for (int k = 0; k < plan.count; ++k) {
    const Octave& octave = plan.octaves[k];
    if (octave.noise_weight == 0.0f) {
      sum += octave.mean_term;
      continue;
    }
    float noise = basis_noise(plan.basis, p * octave.frequency);
    if (plan.absolute) noise = std::fabs(noise);
    sum += octave.noise_weight * noise + octave.mean_term;
  }
  return sum;
}

// The colour of a field of two values, low and high, averaged to t: the blend of the two
// values' colours.
glm::vec3 two_valued_colour(const ColourRamp& ramp, float low, float high, float t) {
  if (high < low) std::swap(low, high);
  return ColourRamp{{{low, ramp.at(low)}, {high, ramp.at(high)}}}.at(t);
}

// A texel by the definition: the pattern's field at one point, then its colour: the ramp
// averaged over the field's spread within the box, or for a field of two values their blend.
Texel reference(const TextureSpec& spec, const glm::dvec3& p, const SampleFootprint& f) {
  const glm::dvec3& box = f.box;
  Texel t;
  const auto plan_of = [&](const FractalParams& fractal) { return plan_octaves(fractal, f.width); };
  const auto fractal_texel = [&](const OctavePlan& plan) {
    t.field = fields::normalise_fractal(plan, scalar_fractal_sum(plan, p));
    t.colour = spec.ramp.average(t.field, fields::fractal_spread(plan));
  };
  if (const auto* s = std::get_if<StripesParams>(&spec.pattern)) {
    t.field = fields::stripes(*s, p, box);
    t.colour = two_valued_colour(spec.ramp, 0.0f, 1.0f, t.field);
  } else if (const auto* c = std::get_if<CheckerParams>(&spec.pattern)) {
    t.field = fields::checker(*c, p, box);
    t.colour = two_valued_colour(spec.ramp, 0.0f, 1.0f, t.field);
  } else if (const auto* cube = std::get_if<ColourCubeParams>(&spec.pattern)) {
    t.colour = fields::colour_cube(*cube, p, box);
    t.field = (t.colour.r + t.colour.g + t.colour.b) * (1.0f / 3.0f);
  } else if (const auto* r = std::get_if<RingsParams>(&spec.pattern)) {
    t.field = fields::rings(*r, p, box);
    const double inner = std::clamp(r->base, 0.0, 1.0);
    const double outer = std::clamp(r->base + r->amplitude, 0.0, 1.0);
    t.colour =
        two_valued_colour(spec.ramp, static_cast<float>(inner), static_cast<float>(outer), t.field);
  } else if (const auto* w = std::get_if<WoodParams>(&spec.pattern)) {
    const fields::WoodFrame frame{std::cos(w->tilt_z), std::sin(w->tilt_z)};
    t.field = fields::wood(*w, frame, fields::wood_rotation(*w, p.y), p, box);
    t.colour = two_valued_colour(spec.ramp, 0.0f, 1.0f, t.field);
  } else if (const auto* n = std::get_if<NoiseParams>(&spec.pattern)) {
    fractal_texel(plan_of(fields::single_octave(*n)));
  } else if (const auto* turbulence = std::get_if<TurbulenceParams>(&spec.pattern)) {
    fractal_texel(plan_of(turbulence->fractal));
  } else {
    const auto& m = std::get<MarbleParams>(spec.pattern);
    const OctavePlan plan = plan_of(m.turbulence);
    const double width = fields::ripple_width(m, p, box);
    const double sine = fields::marble_sine(m, fields::ripple(m, p), scalar_fractal_sum(plan, p));
    t.field = fields::marble_of_sine(sine, fields::marble_fade(width));
    t.colour = spec.ramp.average(
        t.field, fields::marble_spread(
                     fields::marble_spread_terms(m, width, plan.unresolved_variance), sine));
  }
  return t;
}

std::vector<Pattern> all_patterns() {
  MarbleParams product;
  product.ripple = Ripple::product;
  MarbleParams gradient_marble;
  gradient_marble.turbulence.basis = NoiseBasis::gradient;
  MarbleParams along_y;
  along_y.axis = Axis::y;
  MarbleParams along_z;
  along_z.axis = Axis::z;
  along_z.frequency = 1e4;  // ripples far finer than the box: the fade is near 0
  return {StripesParams{0.3, 0.1, Axis::y},
          CheckerParams{glm::dvec3(0.2, 0.3, 0.4), 0.5, true},
          CheckerParams{glm::dvec3(0.1), 0.0, false},
          ColourCubeParams{0.7},
          RingsParams{},
          WoodParams{},
          NoiseParams{5.0, NoiseBasis::value},
          NoiseParams{5.0, NoiseBasis::gradient},
          TurbulenceParams{{3.0, 0, 7, NoiseBasis::value, false}},
          TurbulenceParams{{3.0, 1, 6, NoiseBasis::gradient, true}},
          TurbulenceParams{{3.0, 0, 5, NoiseBasis::gradient, false}},
          MarbleParams{},
          product,
          gradient_marble,
          along_y,
          along_z};
}

// Points near the origin and far away, on lattice and period boundaries, and not finite.
std::vector<glm::dvec3> points_to_check() {
  std::vector<glm::dvec3> points;
  const double special[] = {0.0, -0.0, 0.5, -0.25, 1.0, 1e9, -1e9, 1e9 + 0.37, kNan, kInf, -kInf};
  for (double a : special) {
    for (double b : {0.3, -0.0, 1e9, kNan, -kInf}) points.push_back({a, b, 0.71});
    points.push_back({0.2, a, -0.4});
    points.push_back({-0.6, 0.45, a});
  }
  std::mt19937_64 rng(23);
  std::uniform_real_distribution<double> u(-40.0, 40.0);
  for (int i = 0; i < 200; ++i) points.push_back({u(rng), u(rng), u(rng)});
  return points;
}

std::string describe(const glm::dvec3& p) {
  return "(" + std::to_string(p.x) + ", " + std::to_string(p.y) + ", " + std::to_string(p.z) + ")";
}

TEST(PatternKernels, EveryTargetSamplesPointsAsTheScalarDefinition) {
  const std::vector<int64_t> targets = targets_to_run();
  ASSERT_FALSE(targets.empty());
  const std::vector<glm::dvec3> points = points_to_check();
  const SampleFootprint footprints[] = {
      {0.0, glm::dvec3(0.0)}, {0.01, glm::dvec3(0.01)}, {0.3, glm::dvec3(0.2, 0.0, 0.05)}};
  for (const int64_t target : targets) {
    const test::ForcedTarget forced(target);
    ASSERT_EQ(pattern_kernels::dispatched_target(), target) << hwy::TargetName(target);
    for (const Pattern& pattern : all_patterns()) {
      TextureSpec spec;
      spec.pattern = pattern;
      const TextureEvaluator evaluator(spec);
      for (const SampleFootprint& footprint : footprints) {
        const std::vector<SampleFootprint> each(points.size(), footprint);
        std::vector<Texel> out(points.size());
        evaluator.sample(points, each, out);
        for (std::size_t i = 0; i < points.size(); ++i) {
          const Texel expected = reference(evaluator.spec(), points[i], footprint);
          const std::string where = std::string(hwy::TargetName(target)) + " " +
                                    pattern_name(pattern) + " at " + describe(points[i]) +
                                    " width " + std::to_string(footprint.width);
          ASSERT_TRUE(same(out[i].field, expected.field))
              << where << ": " << out[i].field << " != " << expected.field;
          for (int c = 0; c < 3; ++c) {
            ASSERT_TRUE(same(out[i].colour[c], expected.colour[c])) << where << " channel " << c;
          }
        }
      }
    }
  }
}

// Ramps beyond the patterns' defaults: keys inside (0, 1), two at one position, one key
// alone, and none.
std::vector<ColourRamp> ramps_to_check() {
  const glm::vec3 a{0.1f, 0.7f, 0.3f}, b{0.9f, 0.2f, 0.6f}, c{0.33f, 0.33f, 1.0f};
  return {ColourRamp{{{0.2f, a}, {0.2f, b}, {0.45f, c}, {0.9f, a}}}, ColourRamp{{{0.6f, c}}},
          ColourRamp{},
          // Ending at 0 and at 1: sums of the steps' changes that could miss the range.
          ColourRamp{{{0.0f, c}, {0.3f, b}, {0.5f, glm::vec3(1.0f)}, {0.7f, glm::vec3(0.0f)}}}};
}

// A grid of `spec`'s texture against the scalar definition, point by point, every plane.
void expect_grid_as_definition(const TextureEvaluator& evaluator, const Grid& grid, double width,
                               const std::string& what) {
  const std::size_t n = grid.size();
  std::vector<float> out(n * 5);
  evaluator.evaluate_grid(grid, width, out);
  std::size_t i = 0;
  for (int z = 0; z < grid.count.z; ++z) {
    for (int y = 0; y < grid.count.y; ++y) {
      for (int x = 0; x < grid.count.x; ++x, ++i) {
        const glm::dvec3 p = grid.point(x, y, z);
        const Texel expected = reference(evaluator.spec(), p, SampleFootprint::isotropic(width));
        const std::string where = what + " " + pattern_name(evaluator.spec().pattern) + " at " +
                                  describe(p) + " width " + std::to_string(width);
        for (int c = 0; c < 3; ++c) {
          ASSERT_TRUE(same(out[static_cast<std::size_t>(c) * n + i], expected.colour[c]))
              << where << " channel " << c;
        }
        ASSERT_TRUE(same(out[3 * n + i], expected.field)) << where << " opacity";
        ASSERT_TRUE(same(out[4 * n + i], expected.field)) << where << " specular";
      }
    }
  }
}

TEST(PatternKernels, EveryTargetMapsGridsThroughAnyRampAsTheScalarDefinition) {
  // Rows of 17 and of 41, and grids of 255 and 123 points (the ramp runs over a whole grid):
  // whole vectors and a scalar remainder on every target.
  const Grid grids[] = {
      {{-1.0, -0.5, 0.25}, {0.037, 0.05, 0.11}, {17, 5, 3}},
      {{3.0, -2.0, 1e9}, {0.3, 0.013, 0.2}, {41, 3, 1}},
      {{-0.5, -0.25, 0.3}, {0.0625, 0.0625, 0.1}, {17, 5, 3}},  // x = y = 0 at (8, 4)
  };
  for (const int64_t target : targets_to_run()) {
    const test::ForcedTarget forced(target);
    ASSERT_EQ(pattern_kernels::dispatched_target(), target) << hwy::TargetName(target);
    // Marble's product ripple through the origin with no faded octave: the points at x = 0 have
    // no spread, their neighbours do, so vectors mix averaged lanes with at()'s.
    MarbleParams product;
    product.ripple = Ripple::product;
    product.turbulence = {0.5, 0, 1, NoiseBasis::value, false};
    for (const Pattern& pattern :
         {Pattern{MarbleParams{}}, Pattern{WoodParams{}}, Pattern{product},
          Pattern{TurbulenceParams{{3.0, 0, 7, NoiseBasis::gradient, true}}}}) {
      for (const ColourRamp& ramp : ramps_to_check()) {
        TextureSpec spec;
        spec.pattern = pattern;
        spec.ramp = ramp;
        spec.channels = {true, true, true};
        const TextureEvaluator evaluator(spec);
        for (const Grid& grid : grids) {
          for (double width : {0.0, 0.02}) {
            expect_grid_as_definition(evaluator, grid, width,
                                      std::string(hwy::TargetName(target)) + " ramp of " +
                                          std::to_string(ramp.keys.size()) + " keys,");
          }
        }
      }
    }
  }
}

TEST(PatternKernels, EveryTargetEvaluatesGridsAsTheScalarDefinition) {
  const std::vector<int64_t> targets = targets_to_run();
  const Grid grids[] = {
      {{-1.0, -0.5, 0.25}, {0.037, 0.05, 0.11}, {23, 5, 3}},
      {{1e9 + 0.3, -1e9, -0.0}, {0.001, 0.013, 0.2}, {40, 2, 2}},
      {{-0.0, -0.0, -0.0}, {0.25, 0.25, 0.25}, {17, 3, 1}, {-8, 0, 0}},
      {{kInf, 0.5, kNan}, {0.1, 0.1, 0.1}, {5, 2, 1}},
  };
  for (const int64_t target : targets) {
    const test::ForcedTarget forced(target);
    ASSERT_EQ(pattern_kernels::dispatched_target(), target) << hwy::TargetName(target);
    for (const Pattern& pattern : all_patterns()) {
      TextureSpec spec;
      spec.pattern = pattern;
      spec.channels = {true, true, true};
      const TextureEvaluator evaluator(spec);
      for (const Grid& grid : grids) {
        for (double width : {0.0, 0.02}) {
          const std::size_t n = grid.size();
          std::vector<float> out(n * 5);
          evaluator.evaluate_grid(grid, width, out);
          std::size_t i = 0;
          for (int z = 0; z < grid.count.z; ++z) {
            for (int y = 0; y < grid.count.y; ++y) {
              for (int x = 0; x < grid.count.x; ++x, ++i) {
                const glm::dvec3 p = grid.point(x, y, z);
                const Texel expected =
                    reference(evaluator.spec(), p, SampleFootprint::isotropic(width));
                const std::string where = std::string(hwy::TargetName(target)) + " " +
                                          pattern_name(pattern) + " at " + describe(p);
                for (int c = 0; c < 3; ++c) {
                  ASSERT_TRUE(same(out[static_cast<std::size_t>(c) * n + i], expected.colour[c]))
                      << where << " channel " << c;
                }
                ASSERT_TRUE(same(out[3 * n + i], expected.field)) << where << " opacity";
                ASSERT_TRUE(same(out[4 * n + i], expected.field)) << where << " specular";
              }
            }
          }
        }
      }
    }
  }
}

// Far from the trunk's axis the twist, not the radius, sets how fast the rings pass along y:
// 0.5 rad per unit at 12 units out moves a point 6 units per unit of y, 60 rings of 0.1. A box
// along y is then many rings wide and its wood the rings' average, which the filter must know.
TEST(PatternKernels, WoodFarFromItsAxisAveragesTheTwistedRingsInABox) {
  WoodParams w;
  w.jitter = 0.0;  // the rings alone
  const fields::WoodFrame frame{std::cos(w.tilt_z), std::sin(w.tilt_z)};
  const auto wood_at = [&](const glm::dvec3& p, const glm::dvec3& box) {
    return static_cast<double>(fields::wood(w, frame, fields::wood_rotation(w, p.y), p, box));
  };
  for (const glm::dvec3 p : {glm::dvec3(0.0, 0.3, 12.0), glm::dvec3(-8.0, 1.0, 9.0)}) {
    const double height = 0.04;
    constexpr int kSamples = 20000;
    double sum = 0.0;
    for (int i = 0; i < kSamples; ++i) {
      const double y = p.y - 0.5 * height + (i + 0.5) * height / kSamples;
      sum += wood_at({p.x, y, p.z}, glm::dvec3(0.0));
    }
    EXPECT_NEAR(wood_at(p, {0.0, height, 0.0}), sum / kSamples, 0.05) << p.x << " " << p.z;
  }
}

}  // namespace
}  // namespace soltex
