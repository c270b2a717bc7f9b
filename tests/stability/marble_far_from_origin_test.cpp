// Marble far from the origin (1e6, 1e9): the ripple's phase and the turbulence both keep
// their precision.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "double_reference.h"
#include "soltex/common/brick_evaluator.h"
#include "soltex/common/texture_evaluator.h"

namespace soltex {
namespace {

// For RecordProperty: 3 significant digits in any magnitude (std::to_string prints 1e-7 as 0).
std::string short_number(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3g", v);
  return text;
}

// Tolerance, derived. Raw turbulence (octaves 0..6, value noise): each octave's noise error
// (at most 6.6e-7) weighted by 2^-k sums to under 1.4e-6; the weighted term and the running
// sum (below 2) are rounded once each per octave, 14 * 2^-23 = 1.7e-6. The field
// 0.5 + 0.5 sin(2 pi fract(ripple) + A turb) changes by at most A / 2 = 2 per unit of turb:
// 6.2e-6. The library forms the ripple f x in double: at 1e9 with f = 1.5 that is rounded by
// half of 2.4e-7, 7.5e-7 of phase, 3.8e-7 of field. The final cast to float adds 3e-8. Sum:
// under 7e-6; allowed 1e-5.
constexpr double kTolerance = 1e-5;

MarbleParams marble_params(Ripple ripple = Ripple::axis) {
  MarbleParams m;
  m.frequency = 1.5;
  m.amplitude = 4.0;
  m.ripple = ripple;
  m.turbulence.scale = 2.0;
  m.turbulence.octave_max = 6;
  return m;
}

TextureSpec spec_of(const MarbleParams& m) {
  TextureSpec spec;
  spec.pattern = m;
  return spec;
}

class MarbleFarFromOrigin : public ::testing::TestWithParam<double> {};

INSTANTIATE_TEST_SUITE_P(Offsets, MarbleFarFromOrigin, ::testing::Values(1e6, 1e9, -1e9));

// Expected: at points within two units of (offset, offset / 2, -offset), the double reference
// within 1e-5, point-sampled and band-limited; and the field still spans its range there
// (a float coordinate at 1e9 would step by 64 units and give a few constant values).
TEST_P(MarbleFarFromOrigin, SampleMatchesTheReference) {
  const MarbleParams m = marble_params();
  const TextureEvaluator evaluator(spec_of(m));
  const glm::dvec3 centre(GetParam(), GetParam() / 2, -GetParam());
  std::mt19937_64 rng(31);
  std::uniform_real_distribution<double> u(-2.0, 2.0);
  for (double width : {0.0, 0.01, 0.1}) {
    double lo = 1.0, hi = 0.0, worst = 0.0;
    for (int n = 0; n < 20000; ++n) {
      const glm::dvec3 p = centre + glm::dvec3(u(rng), u(rng), u(rng));
      const float field = evaluator.sample(p, width).field;
      const double error = std::fabs(field - reference::marble(m, width, p));
      worst = std::max(worst, error);
      ASSERT_LE(error, kTolerance) << p.x << " " << p.y << " " << p.z << " width " << width;
      lo = std::min<double>(lo, field);
      hi = std::max<double>(hi, field);
    }
    EXPECT_LT(lo, 0.05);
    EXPECT_GT(hi, 0.95);
    RecordProperty("worst_error_width_" + short_number(width), short_number(worst));
  }
}

// The same through evaluate_brick: a brick of a cache cube that sits at the offset, every
// sample at its grid point.
TEST_P(MarbleFarFromOrigin, BrickSamplesMatchTheReference) {
  const MarbleParams m = marble_params();
  const TextureEvaluator evaluator(spec_of(m));
  const glm::dvec3 centre(GetParam(), GetParam() / 2, -GetParam());
  const BrickLayout layout(Volume{centre - 1.0, centre + 1.0, 6}, 16);
  for (int level : {0, layout.coarsest_level()}) {
    const glm::ivec3 brick(level == 0 ? 2 : 0, level == 0 ? 1 : 0, 0);
    std::vector<float> out(static_cast<std::size_t>(layout.samples_per_brick()) * 3);
    evaluate_brick(evaluator, layout, level, brick, MipSettings{}, out);
    const Grid grid = layout.sample_grid(level, brick);
    std::vector<float> field(grid.size());
    TextureSpec scalar = spec_of(m);
    scalar.channels = {false, true, false};  // opacity = field (low 0, high 1)
    TextureEvaluator(scalar).evaluate_grid(grid, layout.filter_width(level), field);
    std::size_t i = 0;
    for (int k = 0; k < grid.count.z; ++k) {
      for (int j = 0; j < grid.count.y; ++j) {
        for (int x = 0; x < grid.count.x; ++x, ++i) {
          const glm::dvec3 p = grid.point(x, j, k);
          ASSERT_NEAR(field[i], reference::marble(m, layout.filter_width(level), p), kTolerance)
              << "level " << level << " at " << x << " " << j << " " << k;
          // The colour planes are the colour of the same field, as a sample at the point.
          ASSERT_EQ(out[i], evaluator.sample(p, layout.filter_width(level)).colour.r);
        }
      }
    }
  }
}

// The slides' literal ripple f x y z far from the origin is f times a product of 1e9 or more;
// beyond about 1e3 per coordinate double cannot hold its fraction, so it is checked where it
// can: coordinates near -1000, where the product is about 1e9 and double's rounding of it
// (two products, 2^-53 each relative: 2.2e-7) adds 7e-7 to the field.
TEST(MarbleFarFromOrigin, ProductRippleMatchesTheReferenceWhereDoubleHoldsIt) {
  const MarbleParams m = marble_params(Ripple::product);
  const TextureEvaluator evaluator(spec_of(m));
  std::mt19937_64 rng(32);
  std::uniform_real_distribution<double> u(-1001.0, -999.0);
  for (int n = 0; n < 20000; ++n) {
    const glm::dvec3 p(u(rng), u(rng), u(rng));
    ASSERT_NEAR(evaluator.sample(p).field, reference::marble(m, 0.0, p), kTolerance + 7e-7);
  }
}

}  // namespace
}  // namespace soltex
