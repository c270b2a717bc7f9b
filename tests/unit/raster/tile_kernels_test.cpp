// The tile kernels (client/raster/src/tile_kernels.cpp) on every Highway target the CPU runs:
// a row's run starts against the pixel-by-pixel comparison, and drawing in vector lanes against
// the rasterizer's fragment-by-fragment loop.

#include "tile_kernels.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "../texture/dispatch_targets.h"
#include "raster_test_scenes.h"
#include "soltex/raster/rasterizer.h"
#include "tile_rasterizer.h"

namespace soltex {
namespace {

TEST(RunStarts, EveryTargetFindsTheRunsOfARow) {
  const std::vector<int64_t> targets =
      test::targets_to_run(raster_internal::tile_kernels_compiled_targets());
  // A tile's winner plane, padded as TileRasterizer's: runs of every length from 1 to 64,
  // empty pixels among them, rows of every width.
  std::array<raster_internal::ScreenTriangle, 5> triangles;
  std::vector<const raster_internal::ScreenTriangle*> plane(
      raster_internal::kTileSize * raster_internal::kTileSize + raster_internal::kPlanePadding);
  std::mt19937_64 rng(5);
  for (std::size_t i = 0; i < plane.size();) {
    const std::size_t length = 1 + rng() % (rng() % 4 == 0 ? 64 : 4);
    const auto* winner = rng() % 6 == 0 ? nullptr : &triangles[rng() % triangles.size()];
    for (std::size_t k = 0; k < length && i < plane.size(); ++k) plane[i++] = winner;
  }
  for (const int64_t target : targets) {
    const test::ForcedTarget forced(target);
    for (int row = 0; row < raster_internal::kTileSize; ++row) {
      const auto* winners = plane.data() + row * raster_internal::kTileSize;
      for (int count = 1; count <= raster_internal::kTileSize; ++count) {
        uint64_t expected = 1;
        for (int i = 1; i < count; ++i) {
          expected |= uint64_t{winners[i] != winners[i - 1]} << i;
        }
        ASSERT_EQ(raster_internal::run_starts(winners, count), expected)
            << hwy::TargetName(target) << " row " << row << " count " << count;
      }
    }
  }
}

// Triangles from under a pixel to several tiles wide (so both the 32-bit and 64-bit lanes draw),
// at random depths and facing both ways, overlapping: drawn in vector lanes on each target, they
// leave the G-buffer and fragment counts that counting coverage gives, which draws every
// fragment one at a time.
TEST(DrawKernels, EveryTargetDrawsWhatTheFragmentLoopDraws) {
  const std::vector<int64_t> targets =
      test::targets_to_run(raster_internal::tile_kernels_compiled_targets());
  constexpr int kWidth = 200, kHeight = 150;
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  raster_test::Mesh mesh;
  for (uint32_t i = 0; i < 3000; ++i) {
    // Sizes spread over a log scale: a third from 0.3 to 600 pixels (tiles wholly inside some,
    // cut at one corner by others), the rest mostly small.
    const float size = 0.3f * std::pow(i % 3 == 0 ? 2000.0f : 700.0f,
                                       i % 3 == 0 ? unit(rng) : unit(rng) * unit(rng));
    const glm::vec2 centre(unit(rng) * kWidth, unit(rng) * kHeight);
    // Half of them flat at one of four depths, so that equal depths meet (the first one keeps
    // the pixel); the others sloped.
    const float flat = i % 2 == 0 ? -0.25f * static_cast<float>(rng() % 4) : 1.0f;
    for (int k = 0; k < 3; ++k) {
      const glm::vec2 p = centre + size * glm::vec2(unit(rng) - 0.5f, unit(rng) - 0.5f);
      mesh.positions.push_back({p.x, p.y, flat <= 0.0f ? flat : -unit(rng)});
    }
    mesh.add_triangle(3 * i, 3 * i + 1, 3 * i + 2);
  }
  RasterObject object;
  object.mesh = mesh.view();
  object.closed = false;
  const RasterView view{kWidth, kHeight, raster_test::pixel_ortho(kWidth, kHeight), {}};
  GBuffer reference;
  Rasterizer counting({.threads = 1, .count_coverage = true});
  const RasterStats expected = counting.render(view, std::span(&object, 1), reference);
  ASSERT_GT(expected.fragments_depth_passed, 20000u);
  for (const int64_t target : targets) {
    const test::ForcedTarget forced(target);
    Rasterizer rasterizer({.threads = 1});
    GBuffer g;
    const RasterStats stats = rasterizer.render(view, std::span(&object, 1), g);
    SCOPED_TRACE(hwy::TargetName(target));
    raster_test::expect_same_buffer(g, reference);
    EXPECT_EQ(stats.fragments_rasterized, expected.fragments_rasterized);
    EXPECT_EQ(stats.fragments_depth_passed, expected.fragments_depth_passed);
  }
}

}  // namespace
}  // namespace soltex
