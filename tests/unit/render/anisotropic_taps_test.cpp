#include "soltex/render/anisotropic_taps.h"

#include <gtest/gtest.h>

#include <cmath>
#include <glm/geometric.hpp>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "soltex/common/brick_cache.h"
#include "soltex/render/frame_renderer.h"

namespace soltex::render {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

// The long side over the short one, rounded, from a ratio of 2 up to the most allowed.
TEST(TapCount, IsTheRatioRoundedFromTwoUpToTheMost) {
  EXPECT_EQ(tap_count(1.0f, 1.0f, 8), 1);
  EXPECT_EQ(tap_count(1.99f, 1.0f, 8), 1);
  EXPECT_EQ(tap_count(2.0f, 1.0f, 8), 2);
  EXPECT_EQ(tap_count(2.49f, 1.0f, 8), 2);
  EXPECT_EQ(tap_count(2.5f, 1.0f, 8), 3);
  EXPECT_EQ(tap_count(0.035f, 0.01f, 8), 4);  // 3.5 rounds up
  EXPECT_EQ(tap_count(7.6f, 1.0f, 8), 8);
  EXPECT_EQ(tap_count(100.0f, 1.0f, 8), 8);
  EXPECT_EQ(tap_count(100.0f, 1.0f, 16), 16);
  EXPECT_EQ(tap_count(100.0f, 1.0f, 1), 1) << "anisotropy 1: one lookup";
}

// What the rasterizer writes where a footprint has no direction, and what a hand-made
// G-buffer might hold: one tap, or the most, never 0 or more than the most.
TEST(TapCount, OddFootprintsTakeOneTapOrTheMost) {
  EXPECT_EQ(tap_count(0.0f, 0.0f, 8), 1);  // 0/0: uncovered
  EXPECT_EQ(tap_count(kInf, kInf, 8), 1);  // unbounded, no direction
  EXPECT_EQ(tap_count(kNaN, 1.0f, 8), 1);
  EXPECT_EQ(tap_count(1.0f, kNaN, 8), 1);
  EXPECT_EQ(tap_count(0.5f, 0.0f, 8), 8);  // edge-on: as thin as can be
  EXPECT_EQ(tap_count(kInf, 1.0f, 8), 8);
  EXPECT_EQ(tap_count(1.0f, -1.0f, 8), 1);  // negative: not a footprint
}

// The count without branches is the rule as first written (a branch for below 2, NaN
// included, and one for the most), on every ratio around the thresholds and odd operands.
TEST(TapCount, EqualsTheRuleWithBranches) {
  const auto with_branches = [](float footprint, float minor, int most) {
    const float ratio = footprint / minor;
    if (!(ratio >= 2.0f)) return 1;
    return ratio >= static_cast<float>(most) ? most : static_cast<int>(ratio + 0.5f);
  };
  std::vector<float> values = {0.0f, -0.0f, 1.0f, -1.0f, kInf, -kInf, kNaN, 1e-45f, 3e38f};
  for (int half_steps = 3; half_steps <= 35; ++half_steps) {
    const float h = 0.5f * static_cast<float>(half_steps);  // 1.5, 2, 2.5 ... 17.5
    values.insert(values.end(), {h, std::nextafter(h, 0.0f), std::nextafter(h, kInf)});
  }
  for (float r = 1.5f; r < 17.5f; r += 0.0137f) values.push_back(r);
  for (int most = 1; most <= kMaxTaps; ++most) {
    for (const float footprint : values) {
      for (const float minor : {1.0f, 0.0f, -0.0f, 0.25f, kInf, kNaN, 1e-45f}) {
        EXPECT_EQ(tap_count(footprint, minor, most), with_branches(footprint, minor, most))
            << footprint << " / " << minor << ", most " << most;
      }
    }
  }
}

// The tables' offsets and weights are the operations done at run time, bit for bit (a volatile
// keeps the compiler from folding them).
TEST(TapPosition, TablesHoldTheRunTimeOffsetsAndWeights) {
  volatile double half = 0.5;
  volatile float one = 1.0f;
  const glm::dvec3 origin(0.0);
  const glm::vec3 axis(1.0f, 0.0f, 0.0f);
  for (int n = 1; n <= kMaxTaps; ++n) {
    EXPECT_EQ(tap_weight(n), one / static_cast<float>(n)) << n;
    for (int k = 0; k < n; ++k) {
      const double t = (static_cast<double>(k) + half) / static_cast<double>(n) - half;
      EXPECT_EQ(tap_position(origin, axis, k, n).x, t) << k << " of " << n;
    }
  }
}

// n taps spread evenly over the long side, centred on the point: a box filter along it.
TEST(TapPosition, TapsCoverTheLongSideEvenlyAroundThePoint) {
  const glm::dvec3 p(1e6, -3.0, 0.25);       // far from the origin: offsets stay exact in double
  const glm::vec3 axis(0.0f, 0.03f, 0.04f);  // as long as the footprint, 0.05
  for (const int n : {2, 3, 8}) {
    glm::dvec3 sum(0.0);
    for (int k = 0; k < n; ++k) sum += tap_position(p, axis, k, n) - p;
    EXPECT_NEAR(glm::length(sum), 0.0, 1e-9) << n;
    const glm::dvec3 first = tap_position(p, axis, 0, n);
    const glm::dvec3 last = tap_position(p, axis, n - 1, n);
    EXPECT_NEAR(glm::length(last - first), 0.05 * (n - 1) / n, 1e-9) << n;
    for (int k = 1; k < n; ++k) {
      const glm::dvec3 step = tap_position(p, axis, k, n) - tap_position(p, axis, k - 1, n);
      EXPECT_NEAR(glm::length(step), 0.05 / n, 1e-9) << n << " tap " << k;
    }
  }
}

// RenderOptions::anisotropy is refused outside 1 to kMaxTaps, naming the bound: a pixel's taps
// must fit one batch of evaluated pixels.
TEST(TapCount, TheRendererRefusesAnAnisotropyOutOfRange) {
  BrickCache cache(1u << 20);
  for (const int anisotropy : {0, -3, kMaxTaps + 1, 1000}) {
    try {
      FrameRenderer renderer(cache, RenderOptions{.anisotropy = anisotropy});
      FAIL() << anisotropy << " was accepted";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("1 (one lookup per pixel) to 16, got " +
                                           std::to_string(anisotropy)),
                std::string::npos)
          << e.what();
    }
  }
  EXPECT_NO_THROW(FrameRenderer(cache, RenderOptions{.anisotropy = kMaxTaps}));
}

}  // namespace
}  // namespace soltex::render
