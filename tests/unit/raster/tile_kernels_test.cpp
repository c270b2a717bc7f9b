// The tile kernels (client/raster/src/tile_kernels.cpp) on every Highway target the CPU runs:
// a row's run starts against the pixel-by-pixel comparison.

#include "tile_kernels.h"

#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "../texture/dispatch_targets.h"
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

}  // namespace
}  // namespace soltex
